//! Reflection of a fragment entry point's interface with naga: its `@location` inputs, its output,
//! and the resources (uniform buffers with their layouts, textures, samplers) it uses.

use naga::{
    AddressSpace, Binding, Handle, ImageClass, ImageDimension, Module, ScalarKind, TypeInner,
    proc::Layouter, valid::ModuleInfo,
};

use reproj_instance::contract::{CACHE_OUTPUT, DEPTH_OUTPUT};

mod layout;

use layout::{storage_layout, uniform_leaves};

/// An interface the replay cannot feed (a user error: the shader's, not the machine's). The
/// replay's error turns it into its own `Unsupported`, with the same message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("unsupported: {what}")]
pub struct Unsupported {
    pub what: String,
}

/// A fragment input at a `@location`.
#[derive(Debug, Clone, PartialEq)]
pub struct FragInput {
    pub location: u32,
    /// Number of components (1..=4), of `scalar`.
    pub components: u32,
    /// Their scalar: f32 inputs are fed from the session's vertex attributes; an integer input
    /// (flat: Bevy's `instance_index`, a texture index) is fed 0, the one instance drawn.
    pub scalar: InputScalar,
    /// WGSL interpolation qualifier as written (`perspective`, `linear`, `flat`), if any.
    pub interpolation: Option<String>,
    /// WGSL sampling qualifier (`center`, `centroid`, `sample`, ...), if any.
    pub sampling: Option<String>,
    /// Member or argument name, for messages.
    pub name: String,
}

/// The scalar of a fragment input.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum InputScalar {
    #[default]
    F32,
    I32,
    U32,
}

impl InputScalar {
    /// As WGSL spells it.
    pub fn wgsl(self) -> &'static str {
        match self {
            InputScalar::F32 => "f32",
            InputScalar::I32 => "i32",
            InputScalar::U32 => "u32",
        }
    }

    /// The type of `n` of them (`f32`, `vec3<u32>`).
    pub fn wgsl_type(self, n: u32) -> String {
        if n == 1 {
            self.wgsl().to_owned()
        } else {
            format!("vec{n}<{}>", self.wgsl())
        }
    }

    /// Whether it is an integer (fed 0, flat).
    pub fn is_integer(self) -> bool {
        self != InputScalar::F32
    }
}

/// Scalar type of a uniform leaf.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScalarTy {
    F32,
    I32,
    U32,
}

/// A leaf of a uniform (or storage) buffer: a scalar, vector or matrix, or a fixed-size array of
/// them, which the replay fills by name.
#[derive(Debug, Clone, PartialEq)]
pub struct UniformField {
    /// The leaf's path from the buffer's struct: a member name (`shininess`), members of nested
    /// structs joined by dots (`sun.color`), elements of arrays of structs indexed
    /// (`lights[2].position`).
    pub name: String,
    /// Byte offset within the buffer.
    pub offset: u32,
    pub scalar: ScalarTy,
    /// Components per column (1 for scalars, N for vecN, R for matCxR).
    pub rows: u32,
    /// Columns (1 unless a matrix).
    pub cols: u32,
    /// Byte stride between columns.
    pub col_stride: u32,
    /// Array element count (1 if not an array) and stride.
    pub count: u32,
    pub stride: u32,
    /// WGSL-ish type for messages.
    pub ty: String,
}

impl UniformField {
    /// Number of scalars the session must provide.
    pub fn len(&self) -> usize {
        (self.rows * self.cols * self.count) as usize
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Write `values` (column-major, arrays flattened) into `buf`.
    pub fn write(&self, buf: &mut [u8], values: &[f64]) {
        let mut k = 0;
        for e in 0..self.count {
            for c in 0..self.cols {
                for r in 0..self.rows {
                    let off =
                        (self.offset + e * self.stride + c * self.col_stride + r * 4) as usize;
                    let x = values.get(k).copied().unwrap_or(0.0);
                    let bytes = match self.scalar {
                        ScalarTy::F32 => (x as f32).to_le_bytes(),
                        ScalarTy::I32 => (x.round() as i32).to_le_bytes(),
                        ScalarTy::U32 => (x.round().max(0.0) as u32).to_le_bytes(),
                    };
                    if off + 4 <= buf.len() {
                        buf[off..off + 4].copy_from_slice(&bytes);
                    }
                    k += 1;
                }
            }
        }
    }
}

/// A read-only storage buffer's layout: its fixed leaves and, when it ends in a runtime-sized
/// array, where that array lies and the leaves of one element. The element count comes from the
/// session ([`StorageLayout::with_len`]).
#[derive(Debug, Clone, PartialEq)]
pub struct StorageLayout {
    /// naga's size of the buffer's type (with one element of a runtime-sized array).
    pub size: u32,
    /// The leaves outside the runtime-sized array.
    pub fields: Vec<UniformField>,
    pub runtime: Option<RuntimeArray>,
}

/// The runtime-sized array a storage buffer ends with.
#[derive(Debug, Clone, PartialEq)]
pub struct RuntimeArray {
    /// Its path in the buffer (`lights`; empty when the buffer is the array).
    pub name: String,
    pub offset: u32,
    pub stride: u32,
    /// The leaves of element 0, named from the element (`position`, `color`); one leaf with an
    /// empty name when the element is a scalar, vector or matrix.
    pub element: Vec<UniformField>,
}

impl StorageLayout {
    /// The buffer's size and leaves with `n` elements in its runtime-sized array: the elements of
    /// an array of structs are leaves `lights[i].position`, an array of scalars, vectors or
    /// matrices is one leaf of `n` elements.
    pub fn with_len(&self, n: u32) -> (u32, Vec<UniformField>) {
        let mut fields = self.fields.clone();
        let Some(rt) = &self.runtime else {
            return (self.size, fields);
        };
        match rt.element.as_slice() {
            [one] if one.name.is_empty() => fields.push(UniformField {
                name: rt.name.clone(),
                offset: rt.offset,
                count: n,
                stride: rt.stride,
                ..one.clone()
            }),
            element => {
                for i in 0..n {
                    for e in element {
                        fields.push(UniformField {
                            name: format!("{}[{i}].{}", rt.name, e.name),
                            offset: rt.offset + i * rt.stride + e.offset,
                            ..e.clone()
                        });
                    }
                }
            }
        }
        let size = self.size.max(rt.offset + n * rt.stride);
        (size.next_multiple_of(4), fields)
    }
}

/// Texture dimensionality the replay can provide.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TexDim {
    D2,
    /// `texture_2d_array`: layers of 2D images of one size.
    D2Array,
    D3,
    Cube,
}

/// What a resource binding is.
#[derive(Debug, Clone, PartialEq)]
pub enum ResourceKind {
    /// `var<uniform>`: a struct (fields filled by name) or a plain value (filled by the variable's
    /// name, as one field at offset 0).
    Uniform {
        size: u32,
        fields: Vec<UniformField>,
    },
    /// `var<storage, read>`: filled from the session's `buffers` by the variable's name.
    Storage(StorageLayout),
    /// A float texture (`texture_2d<f32>`, `texture_2d_array<f32>`, `texture_cube<f32>`,
    /// `texture_3d<f32>`).
    Texture {
        dim: TexDim,
    },
    /// `texture_depth_2d`.
    DepthTexture,
    Sampler {
        comparison: bool,
    },
    /// Something the replay cannot provide (read-write storage buffers, storage or integer
    /// textures, arrays of textures, multisampled textures). The string says what.
    Unsupported(String),
}

/// A resource the entry point uses.
#[derive(Debug, Clone, PartialEq)]
pub struct Resource {
    pub group: u32,
    pub binding: u32,
    /// Variable name.
    pub name: String,
    pub kind: ResourceKind,
}

/// The interface of one fragment entry point.
#[derive(Debug, Clone)]
pub struct Interface {
    pub entry: String,
    pub entry_index: usize,
    pub inputs: Vec<FragInput>,
    /// Resources used by the entry point (directly or through called functions).
    pub resources: Vec<Resource>,
}

impl Interface {
    /// Group indices used.
    pub fn groups(&self) -> Vec<u32> {
        let mut g: Vec<u32> = self.resources.iter().map(|r| r.group).collect();
        g.sort_unstable();
        g.dedup();
        g
    }
}

fn interp_name(i: naga::Interpolation) -> &'static str {
    match i {
        naga::Interpolation::Perspective => "perspective",
        naga::Interpolation::Linear => "linear",
        naga::Interpolation::Flat => "flat",
        naga::Interpolation::PerVertex => "per_vertex",
    }
}

fn sampling_name(s: naga::Sampling) -> &'static str {
    match s {
        naga::Sampling::Center => "center",
        naga::Sampling::Centroid => "centroid",
        naga::Sampling::Sample => "sample",
        naga::Sampling::First => "first",
        naga::Sampling::Either => "either",
    }
}

/// The components and scalar of an input of type `ty`: 32-bit floats or integers, 1 to 4.
fn input_components(module: &Module, ty: Handle<naga::Type>) -> Option<(u32, InputScalar)> {
    let of = |s: naga::Scalar| match (s.kind, s.width) {
        (ScalarKind::Float, 4) => Some(InputScalar::F32),
        (ScalarKind::Sint, 4) => Some(InputScalar::I32),
        (ScalarKind::Uint, 4) => Some(InputScalar::U32),
        _ => None,
    };
    match module.types[ty].inner {
        TypeInner::Scalar(s) => Some((1, of(s)?)),
        TypeInner::Vector { size, scalar } => Some((size as u32, of(scalar)?)),
        _ => None,
    }
}

fn float_components(module: &Module, ty: Handle<naga::Type>) -> Option<u32> {
    match module.types[ty].inner {
        TypeInner::Scalar(s) if s.kind == ScalarKind::Float && s.width == 4 => Some(1),
        TypeInner::Vector { size, scalar }
            if scalar.kind == ScalarKind::Float && scalar.width == 4 =>
        {
            Some(size as u32)
        }
        _ => None,
    }
}

/// A type as WGSL spells it (`texture_2d_array<f32>`, `DirectionalLight`), by naga's own printer.
fn type_text(module: &Module, ty: Handle<naga::Type>) -> String {
    use naga::common::wgsl::TypeContext;
    let t = &module.types[ty];
    if let Some(n) = &t.name {
        return n.clone();
    }
    let mut out = String::new();
    match module.types.write_type_inner(&t.inner, &mut out) {
        Ok(()) => out,
        Err(_) => format!("{:?}", t.inner),
    }
}

fn collect_input(
    module: &Module,
    name: &str,
    ty: Handle<naga::Type>,
    binding: &Option<Binding>,
    out: &mut Vec<FragInput>,
    entry: &str,
) -> Result<(), Unsupported> {
    match binding {
        Some(Binding::BuiltIn(_)) => Ok(()),
        Some(Binding::Location {
            location,
            interpolation,
            sampling,
            ..
        }) => {
            let (components, scalar) = input_components(module, ty).ok_or_else(|| Unsupported {
                what: format!(
                    "fragment input `{name}` at @location({location}) of `{entry}` has type {}; the replay feeds only 32-bit scalars and vectors",
                    type_text(module, ty)
                ),
            })?;
            out.push(FragInput {
                location: *location,
                components,
                scalar,
                interpolation: interpolation.map(|i| interp_name(i).to_owned()),
                sampling: sampling.map(|s| sampling_name(s).to_owned()),
                name: name.to_owned(),
            });
            Ok(())
        }
        None => match &module.types[ty].inner {
            TypeInner::Struct { members, .. } => {
                for m in members {
                    collect_input(
                        module,
                        m.name.as_deref().unwrap_or("?"),
                        m.ty,
                        &m.binding,
                        out,
                        entry,
                    )?;
                }
                Ok(())
            }
            _ => Err(Unsupported {
                what: format!("fragment argument `{name}` of `{entry}` has no binding"),
            }),
        },
    }
}

/// The entry point's output: one vec4<f32> at @location(0); a variant's pass may add its cache
/// output (`reproj_cache`, a vec4<f32>) and its depth copy (`reproj_depth`, an f32) at higher
/// locations, and builtins.
fn check_output(module: &Module, ep: &naga::EntryPoint) -> Result<(), Unsupported> {
    if let Some(res) = &ep.function.result {
        let ok = match &res.binding {
            Some(Binding::Location { location: 0, .. }) => {
                float_components(module, res.ty) == Some(4)
            }
            None => match &module.types[res.ty].inner {
                TypeInner::Struct { members, .. } => members.iter().all(|m| match &m.binding {
                    Some(Binding::Location { location: 0, .. }) => {
                        float_components(module, m.ty) == Some(4)
                    }
                    Some(Binding::Location { .. }) => match m.name.as_deref() {
                        Some(CACHE_OUTPUT) => float_components(module, m.ty) == Some(4),
                        Some(DEPTH_OUTPUT) => float_components(module, m.ty) == Some(1),
                        _ => false,
                    },
                    Some(Binding::BuiltIn(_)) => true,
                    _ => false,
                }),
                _ => false,
            },
            _ => false,
        };
        if !ok {
            return Err(Unsupported {
                what: format!(
                    "entry point `{}` must return one vec4<f32> at @location(0) (optionally with builtins)",
                    ep.name
                ),
            });
        }
    }
    Ok(())
}

/// What the replay binds for the global `gv` (named `name`), or `None` for a global that is not a
/// resource; what it cannot provide is `ResourceKind::Unsupported` with the reason.
fn resource_kind(
    module: &Module,
    layouter: &Layouter,
    gv: &naga::GlobalVariable,
    name: &str,
) -> Option<ResourceKind> {
    let inner = &module.types[gv.ty].inner;
    let kind = match gv.space {
        AddressSpace::Uniform => {
            let size = layouter[gv.ty].size;
            // A struct's leaves are named from its members; a plain value by the variable.
            let root = match inner {
                TypeInner::Struct { .. } => "",
                _ => name,
            };
            let mut fields = Vec::new();
            match uniform_leaves(module, layouter, root, gv.ty, 0, &mut fields) {
                Ok(()) => ResourceKind::Uniform { size, fields },
                Err(e) if root.is_empty() => ResourceKind::Unsupported(format!("`{name}`: {e}")),
                Err(e) => ResourceKind::Unsupported(e),
            }
        }
        AddressSpace::Handle => match *inner {
            TypeInner::Image {
                dim,
                arrayed,
                class,
            } => {
                let d = match (dim, arrayed) {
                    (ImageDimension::D2, false) => Some(TexDim::D2),
                    (ImageDimension::D2, true) => Some(TexDim::D2Array),
                    (ImageDimension::D3, false) => Some(TexDim::D3),
                    (ImageDimension::Cube, false) => Some(TexDim::Cube),
                    _ => None,
                };
                match (class, d) {
                    (
                        ImageClass::Sampled {
                            kind: ScalarKind::Float,
                            multi: false,
                        },
                        Some(dim),
                    ) => ResourceKind::Texture { dim },
                    (ImageClass::Depth { multi: false }, Some(TexDim::D2)) => {
                        ResourceKind::DepthTexture
                    }
                    _ => ResourceKind::Unsupported(format!(
                        "texture `{name}` ({}): the replay provides float 2D, 2D-array, 3D and cube textures and 2D depth textures only",
                        type_text(module, gv.ty)
                    )),
                }
            }
            TypeInner::Sampler { comparison } => ResourceKind::Sampler { comparison },
            _ => ResourceKind::Unsupported(format!(
                "resource `{name}` of type {}",
                type_text(module, gv.ty)
            )),
        },
        AddressSpace::Storage { access } if access.contains(naga::StorageAccess::STORE) => {
            ResourceKind::Unsupported(format!(
                "storage buffer `{name}` is read_write: the replay provides read-only storage buffers"
            ))
        }
        AddressSpace::Storage { .. } => match storage_layout(module, layouter, gv.ty) {
            Ok(layout) => ResourceKind::Storage(layout),
            Err(e) => ResourceKind::Unsupported(format!("storage buffer `{name}`: {e}")),
        },
        _ => return None,
    };
    Some(kind)
}

/// Reflect the fragment entry point `entry_index` of a validated module.
pub fn reflect(
    module: &Module,
    info: &ModuleInfo,
    entry_index: usize,
) -> Result<Interface, Unsupported> {
    let ep = module
        .entry_points
        .get(entry_index)
        .ok_or_else(|| Unsupported {
            what: format!("no entry point #{entry_index}"),
        })?;
    if ep.stage != naga::ShaderStage::Fragment {
        return Err(Unsupported {
            what: format!("entry point `{}` is not a @fragment entry point", ep.name),
        });
    }
    let mut inputs = Vec::new();
    for arg in &ep.function.arguments {
        collect_input(
            module,
            arg.name.as_deref().unwrap_or("?"),
            arg.ty,
            &arg.binding,
            &mut inputs,
            &ep.name,
        )?;
    }
    inputs.sort_by_key(|i| i.location);
    check_output(module, ep)?;

    let mut layouter = Layouter::default();
    layouter.update(module.to_ctx()).map_err(|e| Unsupported {
        what: format!("layout of the module's types: {e}"),
    })?;

    // An override without a default needs a pipeline constant, which the replay does not set:
    // refused here, by name, rather than by wgpu when the pipeline is created.
    if let Some((_, o)) = module.overrides.iter().find(|(_, o)| o.init.is_none()) {
        let name = o.name.as_deref().unwrap_or("an override");
        return Err(Unsupported {
            what: format!(
                "override `{name}` has no default value, and the replay sets no pipeline constants: give it one in the shader (`override {name}: f32 = …;`) to render or analyze it"
            ),
        });
    }
    let fi = info.get_entry_point(entry_index);
    let mut resources = Vec::new();
    for (h, gv) in module.global_variables.iter() {
        if gv.space == AddressSpace::Immediate {
            // Refused here, by name, rather than by wgpu's shader validation later: the whole
            // module is created on the device, so even a block the entry point does not read
            // needs the immediates capability the replay does not ask for.
            let unused = if fi[h].is_empty() {
                " (declared, though this entry point does not read it)"
            } else {
                ""
            };
            return Err(Unsupported {
                what: format!(
                    "`{}` is a push-constant block (naga's immediates){unused}: the replay cannot bind push constants yet; declare its members in a uniform block to render or analyze this shader",
                    gv.name.as_deref().unwrap_or("the immediate block")
                ),
            });
        }
        let resource_space = matches!(
            gv.space,
            AddressSpace::Uniform | AddressSpace::Storage { .. } | AddressSpace::Handle
        );
        if resource_space && gv.binding.is_none() {
            // A resource its host binds by name (Blade's WGSL): wgpu refuses the module at once.
            return Err(Unsupported {
                what: format!(
                    "`{}` has no @group/@binding (its host binds it by name): give every resource of the module @group(G) @binding(B) to render or analyze this shader",
                    gv.name.as_deref().unwrap_or("a resource")
                ),
            });
        }
        if fi[h].is_empty() {
            continue;
        }
        let Some(rb) = &gv.binding else { continue };
        let name = gv
            .name
            .clone()
            .unwrap_or_else(|| format!("group{}_binding{}", rb.group, rb.binding));
        let Some(kind) = resource_kind(module, &layouter, gv, &name) else {
            continue;
        };
        resources.push(Resource {
            group: rb.group,
            binding: rb.binding,
            name,
            kind,
        });
    }
    resources.sort_by_key(|r| (r.group, r.binding));
    Ok(Interface {
        entry: ep.name.clone(),
        entry_index,
        inputs,
        resources,
    })
}

/// Index of the fragment entry point called `name`.
pub fn fragment_entry_index(module: &Module, name: &str) -> Option<usize> {
    module
        .entry_points
        .iter()
        .position(|e| e.stage == naga::ShaderStage::Fragment && e.name == name)
}
