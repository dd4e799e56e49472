//! Combined image samplers split into an image and a sampler, on the SPIR-V word stream.
//!
//! glslang writes GLSL's `sampler2D` as one `OpTypeSampledImage` variable; naga 30's SPIR-V front
//! end reads only separate images and samplers (`OpSampledImage` of two loads), as HLSL compilers
//! write them. SPIRV-Tools has a split-combined-image-sampler pass, but not in the 2023.1 release
//! Debian ships (`spirv-opt --help` lists no such pass); `rspirv` 0.13 would parse and rebuild
//! the module, but the rewrite touches a dozen opcodes and keeps every other word as it is, so it
//! is done by hand on the word stream (with the `spirv` crate's opcode names, which naga uses):
//!
//! - each combined variable keeps its id, name, set and binding, now as the image, and gains a
//!   sampler variable `NAME_sampler` in the same set at the next binding the set leaves free
//!   ([`SplitSampler`]); arrays of combined samplers become an array of images and one of samplers;
//! - each pointer to a combined sampler (variables, access chains, function parameters, call
//!   arguments) travels as two pointers, and each load becomes two loads and an `OpSampledImage`
//!   with the old load's id, so every use of the combined value is unchanged.

use std::collections::{BTreeMap, HashMap};

use spirv::Op;

pub use crate::shader::SplitSampler;

/// A SPIR-V instruction: opcode and operand words.
#[derive(Debug, Clone)]
struct Inst {
    op: u16,
    operands: Vec<u32>,
}

impl Inst {
    fn new(op: Op, operands: Vec<u32>) -> Inst {
        Inst {
            op: op as u16,
            operands,
        }
    }
    fn is(&self, op: Op) -> bool {
        self.op == op as u16
    }
}

const HEADER: usize = 5;
const UNIFORM_CONSTANT: u32 = spirv::StorageClass::UniformConstant as u32;
const DESCRIPTOR_SET: u32 = spirv::Decoration::DescriptorSet as u32;
const BINDING: u32 = spirv::Decoration::Binding as u32;

fn decode(words: &[u32]) -> Result<(Vec<u32>, Vec<Inst>), String> {
    if words.len() < HEADER || words[0] != spirv::MAGIC_NUMBER {
        return Err("not a SPIR-V module (no magic number)".into());
    }
    let mut insts = Vec::new();
    let mut i = HEADER;
    while i < words.len() {
        let count = (words[i] >> 16) as usize;
        if count == 0 || i + count > words.len() {
            return Err(format!("truncated instruction at word {i}"));
        }
        let op = (words[i] & 0xffff) as u16;
        let operands = words[i + 1..i + count].to_vec();
        if operands.len() < min_operands(op) {
            return Err(format!(
                "instruction {op} at word {i} has {} operands, fewer than SPIR-V requires",
                operands.len()
            ));
        }
        insts.push(Inst { op, operands });
        i += count;
    }
    Ok((words[..HEADER].to_vec(), insts))
}

/// The fewest operands SPIR-V allows an instruction this module reads (0 for the others).
fn min_operands(op: u16) -> usize {
    match Op::from_u32(u32::from(op)) {
        Some(Op::TypeSampler | Op::Name) => 1,
        Some(
            Op::TypeSampledImage
            | Op::TypeRuntimeArray
            | Op::TypeFunction
            | Op::FunctionParameter
            | Op::Decorate
            | Op::Source,
        ) => 2,
        Some(
            Op::TypeArray
            | Op::TypePointer
            | Op::Variable
            | Op::AccessChain
            | Op::InBoundsAccessChain
            | Op::Load
            | Op::FunctionCall
            | Op::Line,
        ) => 3,
        _ => 0,
    }
}

/// `map[&id]`, or an error saying the module is not what glslang writes.
fn get(map: &HashMap<u32, u32>, id: u32) -> Result<u32, String> {
    map.get(&id)
        .copied()
        .ok_or_else(|| format!("malformed module: id {id} is used as a combined image sampler's type or variable, and defined otherwise"))
}

fn encode(header: &[u32], insts: &[Inst]) -> Vec<u32> {
    let mut words = header.to_vec();
    for inst in insts {
        words.push(((inst.operands.len() as u32 + 1) << 16) | inst.op as u32);
        words.extend_from_slice(&inst.operands);
    }
    words
}

/// A literal string's text (nul-terminated UTF-8, little-endian words).
pub(super) fn string_of(words: &[u32]) -> String {
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    String::from_utf8_lossy(&bytes[..end]).into_owned()
}

fn string_words(s: &str) -> Vec<u32> {
    let mut bytes = s.as_bytes().to_vec();
    bytes.push(0);
    while !bytes.len().is_multiple_of(4) {
        bytes.push(0);
    }
    bytes
        .chunks(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// The module with its combined image samplers split, and the samplers it split, by group and
/// binding. A module without combined samplers comes back unchanged. Phases: find the combined
/// shapes ([`Shapes::find`]), give each sampler its binding ([`sampler_bindings`]), rewrite the
/// instructions ([`Rewrite`]).
pub fn split_combined_samplers(words: &[u32]) -> Result<(Vec<u32>, Vec<SplitSampler>), String> {
    let (mut header, mut insts) = decode(words)?;
    // New ids are taken past the bound: one near u32::MAX would overflow (SPIR-V ids stay far
    // below 2^22 in practice).
    if header[3] > 1 << 30 {
        return Err(format!(
            "an id bound of {} is past what SPIR-V allows",
            header[3]
        ));
    }
    strip_global_lines(&mut insts);
    let mut ids = Ids { next: header[3] };
    let Some(shapes) = Shapes::find(&insts, &mut ids)? else {
        return Ok((encode(&header, &insts), Vec::new()));
    };
    let (split, sampler_binding) = sampler_bindings(&shapes)?;
    let mut rewrite = Rewrite {
        out: Vec::with_capacity(insts.len() + 4 * shapes.vars.len()),
        shapes,
        sampler_binding,
        ids: &mut ids,
        sampler_declared: false,
    };
    for inst in insts {
        rewrite.inst(inst)?;
    }
    let out = rewrite.out;
    header[3] = ids.next;
    Ok((encode(&header, &out), split))
}

/// The module's id bound, from which new ids are taken in order.
struct Ids {
    next: u32,
}

impl Ids {
    fn fresh(&mut self) -> u32 {
        self.next += 1;
        self.next - 1
    }
}

/// The combined-sampler shapes of a module: sampled-image types (→ their image type) and arrays
/// of them, pointers to either, and the variables of those pointer types, each with the id of
/// its sampler twin; and the bindings and names of the variables.
struct Shapes {
    sampled: HashMap<u32, u32>,
    /// array → its sampler-array twin
    arrays: HashMap<u32, u32>,
    /// pointer → its sampler-pointer twin
    pointers: HashMap<u32, u32>,
    /// combined pointer value → sampler pointer (grows as parameters and access chains are
    /// rewritten)
    twins: HashMap<u32, u32>,
    vars: Vec<u32>,
    /// The module's `OpTypeSampler`, or the id it will be declared with.
    sampler_type: u32,
    decorations: HashMap<(u32, u32), u32>,
    names: HashMap<u32, String>,
}

impl Shapes {
    /// The shapes of `insts`; `None` when the module has no combined sampler.
    fn find(insts: &[Inst], ids: &mut Ids) -> Result<Option<Shapes>, String> {
        let mut sampled: HashMap<u32, u32> = HashMap::new();
        let mut arrays: HashMap<u32, u32> = HashMap::new();
        let mut pointers: HashMap<u32, u32> = HashMap::new();
        let mut twins: HashMap<u32, u32> = HashMap::new();
        let mut vars: Vec<u32> = Vec::new();
        let mut sampler_type = None;
        let mut decorations: HashMap<(u32, u32), u32> = HashMap::new();
        let mut names: HashMap<u32, String> = HashMap::new();
        for inst in insts {
            let o = &inst.operands;
            match Op::from_u32(inst.op as u32) {
                Some(Op::TypeSampler) => sampler_type = Some(o[0]),
                Some(Op::TypeSampledImage) => {
                    sampled.insert(o[0], o[1]);
                }
                Some(Op::TypeArray | Op::TypeRuntimeArray)
                    if sampled.contains_key(&o[1]) || arrays.contains_key(&o[1]) =>
                {
                    arrays.insert(o[0], ids.fresh());
                }
                Some(Op::TypePointer)
                    if sampled.contains_key(&o[2]) || arrays.contains_key(&o[2]) =>
                {
                    pointers.insert(o[0], ids.fresh());
                }
                Some(Op::Variable) if pointers.contains_key(&o[0]) => {
                    if o[2] != UNIFORM_CONSTANT {
                        return Err("a combined image sampler outside uniform storage".into());
                    }
                    vars.push(o[1]);
                    twins.insert(o[1], ids.fresh());
                }
                Some(Op::Decorate)
                    if o.len() >= 3 && (o[1] == DESCRIPTOR_SET || o[1] == BINDING) =>
                {
                    decorations.insert((o[0], o[1]), o[2]);
                }
                Some(Op::Name) => {
                    names.insert(o[0], string_of(&o[1..]));
                }
                _ => {}
            }
        }
        if sampled.is_empty() {
            return Ok(None);
        }
        let sampler_type = sampler_type.unwrap_or_else(|| ids.fresh());
        Ok(Some(Shapes {
            sampled,
            arrays,
            pointers,
            twins,
            vars,
            sampler_type,
            decorations,
            names,
        }))
    }

    /// The image type of a combined type (an array's is itself: its element is rewritten).
    fn image_of(&self, t: u32) -> u32 {
        self.sampled.get(&t).copied().unwrap_or(t)
    }

    /// The sampler type standing beside a combined type.
    fn sampler_of(&self, t: u32) -> Result<u32, String> {
        if self.sampled.contains_key(&t) {
            Ok(self.sampler_type)
        } else {
            get(&self.arrays, t)
        }
    }
}

/// The samplers split, and each variable's sampler `(group, binding)`.
type SamplerBindings = (Vec<SplitSampler>, HashMap<u32, (u32, u32)>);

/// Each sampler takes the next binding its group leaves free, in declaration order: the samplers
/// split, and each variable's sampler `(group, binding)`. A group whose bindings reach
/// `u32::MAX` leaves none free: an error.
fn sampler_bindings(shapes: &Shapes) -> Result<SamplerBindings, String> {
    let past = |group: u32| {
        format!("descriptor set {group} has no binding free past u32::MAX for a split sampler")
    };
    let decorations = &shapes.decorations;
    // The next free binding of each group, in 64 bits: a binding of u32::MAX leaves none.
    let mut free: BTreeMap<u32, u64> = BTreeMap::new();
    for (&(target, kind), &value) in decorations {
        if kind == BINDING {
            let group = decorations
                .get(&(target, DESCRIPTOR_SET))
                .copied()
                .unwrap_or(0);
            let slot = free.entry(group).or_default();
            *slot = (*slot).max(u64::from(value) + 1);
        }
    }
    let mut split = Vec::new();
    let mut sampler_binding: HashMap<u32, (u32, u32)> = HashMap::new();
    for &var in &shapes.vars {
        let Some(&image_binding) = decorations.get(&(var, BINDING)) else {
            continue;
        };
        let group = decorations
            .get(&(var, DESCRIPTOR_SET))
            .copied()
            .unwrap_or(0);
        let slot = free.entry(group).or_default();
        let binding = u32::try_from(*slot).map_err(|_| past(group))?;
        *slot += 1;
        sampler_binding.insert(var, (group, binding));
        split.push(SplitSampler {
            name: shapes
                .names
                .get(&var)
                .cloned()
                .unwrap_or_else(|| format!("id{var}")),
            group,
            image_binding,
            sampler_binding: binding,
        });
    }
    Ok((split, sampler_binding))
}

/// An instruction whose operands from `first` on are a list (a function type's parameters, a
/// call's arguments): each one with a twin in `twins` is followed by its twin.
fn with_twins(op: Op, inst: &Inst, first: usize, twins: &HashMap<u32, u32>) -> Inst {
    let o = &inst.operands;
    let mut operands = o[..first].to_vec();
    for &p in &o[first..] {
        operands.push(p);
        if let Some(&twin) = twins.get(&p) {
            operands.push(twin);
        }
    }
    Inst::new(op, operands)
}

/// The rewrite of the instructions, one at a time in order: each combined shape becomes an image
/// and a sampler twin.
struct Rewrite<'a> {
    shapes: Shapes,
    sampler_binding: HashMap<u32, (u32, u32)>,
    ids: &'a mut Ids,
    out: Vec<Inst>,
    /// `OpTypeSampler` is declared once, before the first sampled-image type.
    sampler_declared: bool,
}

impl Rewrite<'_> {
    /// Rewrite one instruction: a dispatch on its opcode.
    fn inst(&mut self, inst: Inst) -> Result<(), String> {
        let sh = &self.shapes;
        let o = &inst.operands;
        match Op::from_u32(inst.op as u32) {
            Some(Op::TypeSampler) => {
                if !self.sampler_declared {
                    self.out.push(inst);
                    self.sampler_declared = true;
                }
            }
            Some(Op::TypeSampledImage) => {
                if !self.sampler_declared {
                    let t = sh.sampler_type;
                    self.out.push(Inst::new(Op::TypeSampler, vec![t]));
                    self.sampler_declared = true;
                }
                self.out.push(inst);
            }
            Some(Op::TypeArray | Op::TypeRuntimeArray) if sh.arrays.contains_key(&o[0]) => {
                self.array_type(inst)?
            }
            Some(Op::TypePointer) if sh.pointers.contains_key(&o[0]) => self.pointer_type(&inst)?,
            Some(Op::TypeFunction) => {
                let i = with_twins(Op::TypeFunction, &inst, 2, &sh.pointers);
                self.out.push(i);
            }
            Some(Op::Variable) if sh.twins.contains_key(&o[1]) => self.variable(inst)?,
            Some(Op::Decorate)
                if o.len() >= 3 && o[1] == BINDING && sh.twins.contains_key(&o[0]) =>
            {
                self.binding(inst)
            }
            Some(Op::Name) if sh.twins.contains_key(&o[0]) && sh.vars.contains(&o[0]) => {
                self.name(inst)
            }
            Some(Op::FunctionParameter) if sh.pointers.contains_key(&o[0]) => self.parameter(inst),
            Some(Op::AccessChain | Op::InBoundsAccessChain) if sh.twins.contains_key(&o[2]) => {
                self.access_chain(inst)?
            }
            Some(Op::Load) if sh.twins.contains_key(&o[2]) => self.load(&inst)?,
            Some(Op::FunctionCall) => {
                let i = with_twins(Op::FunctionCall, &inst, 3, &sh.twins);
                self.out.push(i);
            }
            _ => self.out.push(inst),
        }
        Ok(())
    }

    /// An array of combined samplers: an array of images, then its sampler-array twin.
    fn array_type(&mut self, inst: Inst) -> Result<(), String> {
        let o = &inst.operands;
        let mut image = o.clone();
        image[1] = self.shapes.image_of(o[1]);
        let mut sampler = o.clone();
        sampler[0] = get(&self.shapes.arrays, o[0])?;
        sampler[1] = self.shapes.sampler_of(o[1])?;
        self.out.push(Inst {
            op: inst.op,
            operands: image,
        });
        self.out.push(Inst {
            op: inst.op,
            operands: sampler,
        });
        Ok(())
    }

    /// A pointer to a combined shape: a pointer to the image, then its sampler-pointer twin.
    fn pointer_type(&mut self, inst: &Inst) -> Result<(), String> {
        let o = &inst.operands;
        let sh = &self.shapes;
        let image = Inst::new(Op::TypePointer, vec![o[0], o[1], sh.image_of(o[2])]);
        let sampler = Inst::new(
            Op::TypePointer,
            vec![get(&sh.pointers, o[0])?, o[1], sh.sampler_of(o[2])?],
        );
        self.out.extend([image, sampler]);
        Ok(())
    }

    /// A combined variable: kept as the image, followed by its sampler variable.
    fn variable(&mut self, inst: Inst) -> Result<(), String> {
        let o = &inst.operands;
        let mut sampler = o.clone();
        sampler[0] = get(&self.shapes.pointers, o[0])?;
        sampler[1] = get(&self.shapes.twins, o[1])?;
        self.out.push(inst);
        self.out.push(Inst::new(Op::Variable, sampler));
        Ok(())
    }

    /// A combined variable's binding: kept for the image, and the sampler's set and binding.
    fn binding(&mut self, inst: Inst) {
        let target = inst.operands[0];
        self.out.push(inst);
        if let Some(&(group, binding)) = self.sampler_binding.get(&target) {
            let twin = self.shapes.twins[&target];
            self.out
                .push(Inst::new(Op::Decorate, vec![twin, DESCRIPTOR_SET, group]));
            self.out
                .push(Inst::new(Op::Decorate, vec![twin, BINDING, binding]));
        }
    }

    /// A combined variable's name: kept for the image, `NAME_sampler` for the sampler.
    fn name(&mut self, inst: Inst) {
        let o = &inst.operands;
        let mut operands = vec![self.shapes.twins[&o[0]]];
        operands.extend(string_words(&format!("{}_sampler", string_of(&o[1..]))));
        self.out.push(inst);
        self.out.push(Inst::new(Op::Name, operands));
    }

    /// A parameter that points to a combined shape: followed by its sampler-pointer twin.
    fn parameter(&mut self, inst: Inst) {
        let (ty, id) = (inst.operands[0], inst.operands[1]);
        let twin = self.ids.fresh();
        self.shapes.twins.insert(id, twin);
        self.out.push(inst);
        self.out.push(Inst::new(
            Op::FunctionParameter,
            vec![self.shapes.pointers[&ty], twin],
        ));
    }

    /// An access chain into a combined array: followed by the same chain into the samplers.
    fn access_chain(&mut self, inst: Inst) -> Result<(), String> {
        let o = &inst.operands;
        let twin_type = *self
            .shapes
            .pointers
            .get(&o[0])
            .ok_or("an access chain into a combined image sampler of an unknown type")?;
        let twin = self.ids.fresh();
        let mut sampler = o.clone();
        sampler[0] = twin_type;
        sampler[1] = twin;
        sampler[2] = self.shapes.twins[&o[2]];
        self.shapes.twins.insert(o[1], twin);
        let op = inst.op;
        self.out.push(inst);
        self.out.push(Inst {
            op,
            operands: sampler,
        });
        Ok(())
    }

    /// A load of a combined sampler: two loads and an `OpSampledImage` with the old load's id, so
    /// every use of the combined value is unchanged.
    fn load(&mut self, inst: &Inst) -> Result<(), String> {
        let o = &inst.operands;
        if !self.shapes.sampled.contains_key(&o[0]) {
            return Err("a whole array of combined image samplers is loaded".into());
        }
        let (image, sampler) = (self.ids.fresh(), self.ids.fresh());
        let mut load_image = o.clone();
        load_image[0] = self.shapes.image_of(o[0]);
        load_image[1] = image;
        let sampler_type = self.shapes.sampler_type;
        self.out.push(Inst::new(Op::Load, load_image));
        self.out.push(Inst::new(
            Op::Load,
            vec![sampler_type, sampler, self.shapes.twins[&o[2]]],
        ));
        self.out.push(Inst::new(
            Op::SampledImage,
            vec![o[0], o[1], image, sampler],
        ));
        Ok(())
    }
}

/// Whether the module holds an `OpSpecConstantOp` (a specialization constant in a constant
/// expression, which naga's reader does not take).
pub(super) fn has_spec_constant_op(words: &[u32]) -> bool {
    decode(words).is_ok_and(|(_, insts)| insts.iter().any(|i| i.is(Op::SpecConstantOp)))
}

/// Drops the `OpLine`s outside functions (glslang's, before global variables), which naga's
/// reader refuses there; the lines inside functions are the ones nodes are placed by.
fn strip_global_lines(insts: &mut Vec<Inst>) {
    let mut in_function = false;
    insts.retain(|inst| {
        if inst.is(Op::Function) {
            in_function = true;
        } else if inst.is(Op::FunctionEnd) {
            in_function = false;
        }
        in_function || !(inst.is(Op::Line) || inst.is(Op::NoLine))
    });
}

/// The bytes of each instruction of `words` (as naga's spans count them) and the source line its
/// `OpLine` gives it in the main file (the one the first `OpSource` names), in order.
/// Instructions without a line are left out.
pub(super) fn line_table(words: &[u32]) -> Vec<(std::ops::Range<usize>, u32)> {
    let Ok((_, insts)) = decode(words) else {
        return Vec::new();
    };
    let mut main_file = None;
    let mut table = Vec::new();
    let mut offset = HEADER * 4;
    let mut current: Option<u32> = None;
    for inst in &insts {
        let o = &inst.operands;
        if inst.is(Op::Source) && o.len() >= 3 && main_file.is_none() {
            main_file = Some(o[2]);
        } else if inst.is(Op::Line) {
            current = (main_file.is_none_or(|f| f == o[0])).then_some(o[1]);
        } else if inst.is(Op::NoLine) || inst.is(Op::FunctionEnd) {
            current = None;
        }
        let end = offset + 4 * (o.len() + 1);
        if let Some(line) = current {
            table.push((offset..end, line));
        }
        if matches!(
            Op::from_u32(inst.op as u32),
            Some(
                Op::Branch
                    | Op::BranchConditional
                    | Op::Switch
                    | Op::Kill
                    | Op::Return
                    | Op::ReturnValue
                    | Op::Unreachable
                    | Op::TerminateInvocation
            )
        ) {
            current = None;
        }
        offset = end;
    }
    table
}
