//! The fused (one-pass) and two-pass strategies.
//!
//! Both are built from three functions placed in one module beside the shader's own code:
//! `reproj_fetch` (the reprojection lookup, imported from `lookup.wgsl`), `reproj_recompute` (the
//! slice of the shader that computes the node, as the three-pass strategy's pass 2 computes it) and
//! `reproj_shade` (the shader with the node read from an extra `vec4<f32>` argument). Small entry
//! points call them:
//!
//! - fused: `fetch`; on a miss or refresh `recompute`; then `shade`; write the color and the new
//!   cache (two color targets);
//! - two-pass, pass 1 (`shade_hits`): `fetch`; discard unless it hit; `shade` the hit; write color
//!   and cache, and depth, which closes the pixel for pass 2;
//! - two-pass, pass 2 (`shade_misses`): where pass 1 left the pixel open, `recompute` then `shade`.
//!
//! The three-pass strategy's shade pass gets a small entry of the same kind: the shader's entry
//! point, read from the cache, becomes `reproj_shade` and the entry calls it.
//!
//! Every entry that writes the frame color also writes the fragment's depth (`@builtin(position).z`)
//! to one more color target, the *depth copy* (r32float): the next frame's lookup reads it as a
//! plain float texture, which every shading language can load (a depth texture is a shadow sampler
//! in GLSL). So the depth buffer never has to be sampled, nor kept from one frame to the next.
//! Where the payload has a channel to spare (`Parts::depth_channel`), the depth goes there
//! instead: one target fewer, and the lookup reads depth and payload in one filtered fetch.
//!
//! The functions are ordinary naga functions; the entry points are built directly in IR.

use crate::library::PrevClip;
use crate::{InstanceError, PassKind};
use naga::{Expression, Function, Handle, Module, Span, Statement, Type};

/// The payload type and the shader's functions, ready for the entry points.
pub(crate) struct Parts {
    pub vec4: Handle<Type>,
    /// `reproj_recompute` (absent from the three-pass shade pass).
    pub recompute: Option<Handle<Function>>,
    pub shade: Handle<Function>,
    /// `reproj_fetch`, when the lookup library was imported.
    pub fetch: Option<Handle<Function>>,
    /// `reproj_motion_clip`, when the library imported reads the engine's motion vectors.
    pub motion_clip: Option<Handle<Function>>,
    /// The output struct: the original outputs, the cache (when written) and the depth copy
    /// (unless the depth is in the payload).
    pub output: Handle<Type>,
    /// The payload channel that carries the fragment's depth, if any (then no depth copy).
    pub depth_channel: Option<u32>,
}

/// How the new entry point's body is put together.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum EntryKind {
    Fused,
    ShadeHits,
    ShadeMisses,
    /// The three-pass strategy's shade pass: `reproj_shade` reads the node from the cache itself.
    Shade,
}

pub(crate) use crate::contract::{CACHE_OUTPUT as CACHE_MEMBER, DEPTH_OUTPUT as DEPTH_MEMBER};

/// Turn the entry point's function into an ordinary function: no bindings, a new name.
pub(crate) fn as_function(mut f: Function, name: &str) -> Function {
    f.name = Some(name.into());
    for a in &mut f.arguments {
        a.binding = None;
    }
    if let Some(r) = &mut f.result {
        r.binding = None;
    }
    f
}

/// The output struct of an entry built here: the shader's outputs, then (with `cache`) the cache
/// payload `reproj_cache: vec4<f32>`, then (with `depth_copy`) the depth copy `reproj_depth: f32`,
/// at the next free locations.
pub(crate) fn output_struct(
    module: &mut Module,
    result: &naga::FunctionResult,
    cache: Option<Handle<Type>>,
    depth_copy: bool,
) -> Handle<Type> {
    let f32_ty = module.types.insert(
        Type {
            name: None,
            inner: naga::TypeInner::Scalar(naga::Scalar::F32),
        },
        Span::UNDEFINED,
    );
    let mut members: Vec<naga::StructMember> =
        match (&result.binding, &module.types[result.ty].inner) {
            (None, naga::TypeInner::Struct { members, .. }) => members.clone(),
            _ => vec![naga::StructMember {
                name: Some("color".into()),
                ty: result.ty,
                binding: result.binding.clone(),
                offset: 0,
            }],
        };
    let max_location = members
        .iter()
        .filter_map(|m| match &m.binding {
            Some(naga::Binding::Location { location, .. }) => Some(*location),
            _ => None,
        })
        .max();
    let first_free = max_location.map_or(0, |l| l + 1);
    let extra = cache
        .map(|ty| (CACHE_MEMBER, ty))
        .into_iter()
        .chain(depth_copy.then_some((DEPTH_MEMBER, f32_ty)));
    for (location, (name, ty)) in (first_free..).zip(extra) {
        members.push(naga::StructMember {
            name: Some(name.into()),
            ty,
            binding: Some(naga::Binding::Location {
                location,
                interpolation: None,
                sampling: None,
                blend_src: None,
                per_primitive: false,
            }),
            offset: 0,
        });
    }
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .expect("the shader's types have a layout");
    let mut offset = 0u32;
    for m in &mut members {
        let l = layouter[m.ty];
        offset = l.alignment.round_up(offset);
        m.offset = offset;
        offset += l.size;
    }
    let span = naga::proc::Alignment::from_width(16).round_up(offset);
    module.types.insert(
        Type {
            name: Some("ReprojOutput".into()),
            inner: naga::TypeInner::Struct { members, span },
        },
        Span::UNDEFINED,
    )
}

/// A function body under construction, with naga's emit ranges kept right.
struct Body {
    fun: Function,
    emitter: naga::proc::Emitter,
    blocks: Vec<naga::Block>,
}

impl Body {
    fn new(fun: Function) -> Body {
        let mut b = Body {
            fun,
            emitter: Default::default(),
            blocks: vec![naga::Block::new()],
        };
        b.emitter.start(&b.fun.expressions);
        b
    }

    fn expr(&mut self, e: Expression) -> Handle<Expression> {
        if e.needs_pre_emit() {
            self.flush();
            let h = self.fun.expressions.append(e, Span::UNDEFINED);
            self.emitter.start(&self.fun.expressions);
            h
        } else {
            self.fun.expressions.append(e, Span::UNDEFINED)
        }
    }

    fn flush(&mut self) {
        if let Some((s, span)) = self.emitter.finish(&self.fun.expressions) {
            self.blocks.last_mut().unwrap().push(s, span);
        }
    }

    fn stmt(&mut self, s: Statement) {
        self.flush();
        self.blocks.last_mut().unwrap().push(s, Span::UNDEFINED);
        self.emitter.start(&self.fun.expressions);
    }

    fn call(
        &mut self,
        function: Handle<Function>,
        arguments: Vec<Handle<Expression>>,
    ) -> Handle<Expression> {
        self.flush();
        let result = self
            .fun
            .expressions
            .append(Expression::CallResult(function), Span::UNDEFINED);
        self.blocks.last_mut().unwrap().push(
            Statement::Call {
                function,
                arguments,
                result: Some(result),
            },
            Span::UNDEFINED,
        );
        self.emitter.start(&self.fun.expressions);
        result
    }

    fn open(&mut self) {
        self.flush();
        self.blocks.push(naga::Block::new());
        self.emitter.start(&self.fun.expressions);
    }

    fn close(&mut self) -> naga::Block {
        self.flush();
        let b = self.blocks.pop().unwrap();
        self.emitter.start(&self.fun.expressions);
        b
    }

    fn finish(mut self) -> Function {
        self.flush();
        self.fun.body = self.blocks.pop().unwrap();
        self.fun
    }
}

/// Build the entry point `kind` of a fused or two-pass module. `entry` is the shader's entry
/// function (its arguments and result); `prev_clip` where the previous clip position comes from
/// (an extra vertex output, or the motion vectors through `reproj_motion_clip`).
/// Phases: the arguments, the body's start (the original arguments and the fragment position),
/// the payload (fetched, recomputed, or both), then the shade call and the output struct.
pub(crate) fn build_entry(
    module: &Module,
    entry: &Function,
    parts: &Parts,
    kind: EntryKind,
    prev_clip: PrevClip,
) -> Result<Function, InstanceError> {
    let EntryArguments {
        arguments,
        original_args,
        position: (pi, member),
        prev_clip,
    } = entry_arguments(module, entry, parts, kind, prev_clip);
    let mut local_variables = naga::Arena::new();
    let payload_var = local_variables.append(
        naga::LocalVariable {
            name: Some("reproj_payload".into()),
            ty: parts.vec4,
            init: None,
        },
        Span::UNDEFINED,
    );
    let mut b = Body::new(Function {
        name: entry.name.clone(),
        arguments,
        result: Some(naga::FunctionResult {
            ty: parts.output,
            binding: None,
        }),
        local_variables,
        expressions: naga::Arena::new(),
        named_expressions: Default::default(),
        body: naga::Block::new(),
        diagnostic_filter_leaf: None,
    });
    let args: Vec<Handle<Expression>> = (0..original_args)
        .map(|i| b.expr(Expression::FunctionArgument(i)))
        .collect();
    let mut pos = b.expr(Expression::FunctionArgument(pi));
    if let Some(m) = member {
        pos = b.expr(Expression::AccessIndex {
            base: pos,
            index: m,
        });
    }
    let start = EntryStart {
        parts,
        kind,
        args,
        pos,
        prev_clip,
        payload_var,
    };
    let payload = payload(&mut b, &start)?;
    let out = entry_output(&mut b, module, entry, &start, payload)?;
    b.stmt(Statement::Return { value: Some(out) });
    let mut fun = b.finish();
    if kind != EntryKind::Fused {
        // The payload variable is only used by the fused body.
        fun.local_variables = naga::Arena::new();
    }
    Ok(fun)
}

/// A bug in reproj while building the entry point `kind`.
fn internal(kind: EntryKind, what: &str) -> InstanceError {
    InstanceError::Internal {
        pass: pass_kind(kind),
        what: what.into(),
    }
}

/// The new entry point's arguments and where the ones it adds are.
struct EntryArguments {
    arguments: Vec<naga::FunctionArgument>,
    /// How many of `arguments` are the shader's own (the shade and recompute calls take them).
    original_args: u32,
    /// The fragment position: an argument, and its member when the argument is a struct.
    position: (u32, Option<u32>),
    /// The previous clip position's argument, for the entries that fetch it from the vertex stage.
    prev_clip: Option<u32>,
}

/// The shader's arguments, plus the fragment position where the shader has none (every entry
/// writes the depth copy) and the previous clip position where the entry fetches it from the
/// vertex stage.
fn entry_arguments(
    module: &Module,
    entry: &Function,
    parts: &Parts,
    kind: EntryKind,
    prev_clip: PrevClip,
) -> EntryArguments {
    let mut arguments = entry.arguments.clone();
    let original_args = arguments.len() as u32;
    // Every entry writes the depth copy, so every one needs the fragment's position.
    let position = match crate::find_position(module, &arguments) {
        Some(p) => p,
        None => {
            arguments.push(naga::FunctionArgument {
                name: Some("reproj_frag_coord".into()),
                ty: parts.vec4,
                binding: Some(naga::Binding::BuiltIn(naga::BuiltIn::Position {
                    invariant: false,
                })),
            });
            (arguments.len() as u32 - 1, None)
        }
    };
    let prev_clip_location = prev_clip.location().filter(|_| needs_fetch(kind));
    let mut prev_clip = None;
    if let Some(prev_clip_location) = prev_clip_location {
        arguments.push(naga::FunctionArgument {
            name: Some("reproj_prev_clip".into()),
            ty: parts.vec4,
            binding: Some(naga::Binding::Location {
                location: prev_clip_location,
                interpolation: Some(naga::Interpolation::Perspective),
                sampling: Some(naga::Sampling::Center),
                blend_src: None,
                per_primitive: false,
            }),
        });
        prev_clip = Some(arguments.len() as u32 - 1);
    }
    EntryArguments {
        arguments,
        original_args,
        position,
        prev_clip,
    }
}

/// What the later phases of an entry point use: its parts and kind, and the handles its start
/// made (the shader's arguments, the fragment position) or declared.
struct EntryStart<'a> {
    parts: &'a Parts,
    kind: EntryKind,
    args: Vec<Handle<Expression>>,
    pos: Handle<Expression>,
    prev_clip: Option<u32>,
    payload_var: Handle<naga::LocalVariable>,
}

impl EntryStart<'_> {
    /// `reproj_recompute`, which the entries that recompute need.
    fn recompute(&self) -> Result<Handle<Function>, InstanceError> {
        self.parts
            .recompute
            .ok_or_else(|| internal(self.kind, "no recompute function"))
    }
}

/// The payload the shade call takes: none (3pass shade), recomputed (shade misses), fetched with
/// the misses discarded (shade hits), or fetched and recomputed where the quad missed (fused).
fn payload(b: &mut Body, s: &EntryStart) -> Result<Option<Handle<Expression>>, InstanceError> {
    let kind = s.kind;
    if kind == EntryKind::Shade {
        return Ok(None);
    }
    if kind == EntryKind::ShadeMisses {
        return Ok(Some(b.call(s.recompute()?, s.args.clone())));
    }
    let fetch = s
        .parts
        .fetch
        .ok_or_else(|| internal(kind, "no lookup library"))?;
    let prev = match (s.prev_clip, s.parts.motion_clip) {
        (Some(arg), _) => b.expr(Expression::FunctionArgument(arg)),
        (None, Some(motion_clip)) => b.call(motion_clip, vec![s.pos]),
        (None, None) => return Err(internal(kind, "no previous clip position")),
    };
    let r = b.call(fetch, vec![s.pos, prev]);
    let fetched = b.expr(Expression::AccessIndex { base: r, index: 0 });
    let status = b.expr(Expression::AccessIndex { base: r, index: 1 });
    let zero = b.expr(Expression::Literal(naga::Literal::U32(0)));
    let missed = b.expr(Expression::Binary {
        op: naga::BinaryOperator::NotEqual,
        left: status,
        right: zero,
    });
    if kind == EntryKind::ShadeHits {
        b.open();
        b.stmt(Statement::Kill);
        let accept = b.close();
        b.stmt(Statement::If {
            condition: missed,
            accept,
            reject: naga::Block::new(),
        });
        return Ok(Some(fetched));
    }
    let quad_missed = quad_missed(b, missed);
    let var = b.expr(Expression::LocalVariable(s.payload_var));
    b.stmt(Statement::Store {
        pointer: var,
        value: fetched,
    });
    b.open();
    let computed = b.call(s.recompute()?, s.args.clone());
    b.stmt(Statement::Store {
        pointer: var,
        value: computed,
    });
    let accept = b.close();
    b.stmt(Statement::If {
        condition: quad_missed,
        accept,
        reject: naga::Block::new(),
    });
    Ok(Some(b.expr(Expression::Load { pointer: var })))
}

/// Whether any pixel of the 2×2 quad missed, from each pixel's `missed`: the fused entry
/// recomputes the whole quad then, so that derivatives in the recompute branch (implicit-LOD
/// texture samples, dpdx) see four active pixels. Fine derivatives of the miss flag reach the
/// horizontal, then the vertical neighbour: `quad` > 0 iff one of the four flags is 1. Refreshed
/// blocks already cover whole quads (k even); misses need not.
fn quad_missed(b: &mut Body, missed: Handle<Expression>) -> Handle<Expression> {
    let fzero = b.expr(Expression::Literal(naga::Literal::F32(0.0)));
    let fone = b.expr(Expression::Literal(naga::Literal::F32(1.0)));
    let flag = b.expr(Expression::Select {
        condition: missed,
        accept: fone,
        reject: fzero,
    });
    let spread = |b: &mut Body, v, axis| {
        let d = b.expr(Expression::Derivative {
            axis,
            ctrl: naga::DerivativeControl::Fine,
            expr: v,
        });
        let a = b.expr(Expression::Math {
            fun: naga::MathFunction::Abs,
            arg: d,
            arg1: None,
            arg2: None,
            arg3: None,
        });
        b.expr(Expression::Binary {
            op: naga::BinaryOperator::Add,
            left: v,
            right: a,
        })
    };
    let row = spread(b, flag, naga::DerivativeAxis::X);
    let quad = spread(b, row, naga::DerivativeAxis::Y);
    b.expr(Expression::Binary {
        op: naga::BinaryOperator::Greater,
        left: quad,
        right: fzero,
    })
}

/// Call the shade function with the payload and compose the output struct: the shader's outputs,
/// the payload (the cache target, where written) and the fragment's depth for the depth copy
/// (`@builtin(position).z`, unless the shader writes its own).
fn entry_output(
    b: &mut Body,
    module: &Module,
    entry: &Function,
    s: &EntryStart,
    payload: Option<Handle<Expression>>,
) -> Result<Handle<Expression>, InstanceError> {
    let mut shade_args = s.args.clone();
    shade_args.extend(payload);
    let color = b.call(s.parts.shade, shade_args);
    let result = entry
        .result
        .as_ref()
        .ok_or_else(|| internal(s.kind, "no result"))?;
    let mut components = Vec::new();
    let mut depth = None;
    match (&result.binding, &module.types[result.ty].inner) {
        (None, naga::TypeInner::Struct { members, .. }) => {
            for (i, m) in members.iter().enumerate() {
                let c = b.expr(Expression::AccessIndex {
                    base: color,
                    index: i as u32,
                });
                if m.binding == Some(naga::Binding::BuiltIn(naga::BuiltIn::FragDepth)) {
                    depth = Some(c);
                }
                components.push(c);
            }
        }
        _ => components.push(color),
    }
    let depth = match depth {
        Some(d) => d,
        None => b.expr(Expression::AccessIndex {
            base: s.pos,
            index: 2,
        }),
    };
    match (payload, s.parts.depth_channel) {
        (Some(payload), Some(channel)) => {
            let packed = with_depth(b, s.parts.vec4, payload, depth, channel);
            components.push(packed);
        }
        (payload, _) => {
            components.extend(payload);
            components.push(depth);
        }
    }
    Ok(b.expr(Expression::Compose {
        ty: s.parts.output,
        components,
    }))
}

/// `payload` with its channel `channel` replaced by `depth`: the cache written where the payload
/// carries the depth.
fn with_depth(
    b: &mut Body,
    vec4: Handle<Type>,
    payload: Handle<Expression>,
    depth: Handle<Expression>,
    channel: u32,
) -> Handle<Expression> {
    let components = (0..4)
        .map(|i| {
            if i == channel {
                depth
            } else {
                b.expr(Expression::AccessIndex {
                    base: payload,
                    index: i,
                })
            }
        })
        .collect();
    b.expr(Expression::Compose {
        ty: vec4,
        components,
    })
}

/// Which entry points a strategy's modules have, in pass order.
pub(crate) fn entries(strategy: crate::Strategy) -> &'static [EntryKind] {
    match strategy {
        crate::Strategy::Fused => &[EntryKind::Fused],
        crate::Strategy::TwoPass => &[EntryKind::ShadeHits, EntryKind::ShadeMisses],
        crate::Strategy::ThreePass => &[],
    }
}

/// The manifest's name for an entry's pass.
pub(crate) fn pass_kind(kind: EntryKind) -> PassKind {
    match kind {
        EntryKind::Fused => PassKind::Fused,
        EntryKind::ShadeHits => PassKind::ShadeHits,
        EntryKind::ShadeMisses => PassKind::ShadeMisses,
        EntryKind::Shade => PassKind::Shade,
    }
}

/// Does this entry need the lookup library?
pub(crate) fn needs_fetch(kind: EntryKind) -> bool {
    matches!(kind, EntryKind::Fused | EntryKind::ShadeHits)
}
