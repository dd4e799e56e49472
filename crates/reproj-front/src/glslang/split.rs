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

/// One combined image sampler of the GLSL shader, as the SPIR-V that reproj reads binds it.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct SplitSampler {
    /// The GLSL name (`albedo`); the image keeps it, the sampler is `NAME_sampler`.
    pub name: String,
    pub group: u32,
    /// The image's binding: the combined sampler's own.
    pub image_binding: u32,
    /// The sampler's binding: the next one the group leaves free.
    pub sampler_binding: u32,
}

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
        insts.push(Inst {
            op: (words[i] & 0xffff) as u16,
            operands: words[i + 1..i + count].to_vec(),
        });
        i += count;
    }
    Ok((words[..HEADER].to_vec(), insts))
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
/// binding. A module without combined samplers comes back unchanged.
pub fn split_combined_samplers(words: &[u32]) -> Result<(Vec<u32>, Vec<SplitSampler>), String> {
    let (mut header, mut insts) = decode(words)?;
    strip_global_lines(&mut insts);
    let mut next_id = header[3];
    let mut fresh = || {
        next_id += 1;
        next_id - 1
    };

    // The combined-sampler shapes: sampled-image types (→ their image type) and arrays of them,
    // pointers to either, and the variables of those pointer types.
    let mut sampled: HashMap<u32, u32> = HashMap::new();
    let mut arrays: HashMap<u32, u32> = HashMap::new(); // array → its sampler-array twin
    let mut pointers: HashMap<u32, u32> = HashMap::new(); // pointer → its sampler-pointer twin
    let mut twins: HashMap<u32, u32> = HashMap::new(); // combined pointer value → sampler pointer
    let mut vars: Vec<u32> = Vec::new();
    let mut sampler_type = None;
    let mut decorations: HashMap<(u32, u32), u32> = HashMap::new();
    let mut names: HashMap<u32, String> = HashMap::new();
    for inst in &insts {
        let o = &inst.operands;
        match Op::from_u32(inst.op as u32) {
            Some(Op::TypeSampler) => sampler_type = Some(o[0]),
            Some(Op::TypeSampledImage) => {
                sampled.insert(o[0], o[1]);
            }
            Some(Op::TypeArray | Op::TypeRuntimeArray)
                if sampled.contains_key(&o[1]) || arrays.contains_key(&o[1]) =>
            {
                arrays.insert(o[0], fresh());
            }
            Some(Op::TypePointer) if sampled.contains_key(&o[2]) || arrays.contains_key(&o[2]) => {
                pointers.insert(o[0], fresh());
            }
            Some(Op::Variable) if pointers.contains_key(&o[0]) => {
                if o[2] != UNIFORM_CONSTANT {
                    return Err("a combined image sampler outside uniform storage".into());
                }
                vars.push(o[1]);
                twins.insert(o[1], fresh());
            }
            Some(Op::Decorate) if o.len() >= 3 && (o[1] == DESCRIPTOR_SET || o[1] == BINDING) => {
                decorations.insert((o[0], o[1]), o[2]);
            }
            Some(Op::Name) => {
                names.insert(o[0], string_of(&o[1..]));
            }
            _ => {}
        }
    }
    if sampled.is_empty() {
        return Ok((encode(&header, &insts), Vec::new()));
    }
    let sampler_type = sampler_type.unwrap_or_else(&mut fresh);

    // Each sampler takes the next binding its group leaves free, in declaration order.
    let mut free: BTreeMap<u32, u32> = BTreeMap::new();
    for (&(target, kind), &value) in &decorations {
        if kind == BINDING {
            let group = decorations
                .get(&(target, DESCRIPTOR_SET))
                .copied()
                .unwrap_or(0);
            let slot = free.entry(group).or_default();
            *slot = (*slot).max(value + 1);
        }
    }
    let mut split = Vec::new();
    let mut sampler_binding: HashMap<u32, (u32, u32)> = HashMap::new();
    for &var in &vars {
        let Some(&image_binding) = decorations.get(&(var, BINDING)) else {
            continue;
        };
        let group = decorations
            .get(&(var, DESCRIPTOR_SET))
            .copied()
            .unwrap_or(0);
        let slot = free.entry(group).or_default();
        let binding = *slot;
        *slot += 1;
        sampler_binding.insert(var, (group, binding));
        split.push(SplitSampler {
            name: names
                .get(&var)
                .cloned()
                .unwrap_or_else(|| format!("id{var}")),
            group,
            image_binding,
            sampler_binding: binding,
        });
    }

    let image_of = |t: u32| sampled.get(&t).copied().unwrap_or(t);
    let sampler_of = |t: u32| {
        if sampled.contains_key(&t) {
            sampler_type
        } else {
            arrays[&t]
        }
    };
    let mut out: Vec<Inst> = Vec::with_capacity(insts.len() + 4 * vars.len());
    let mut sampler_declared = false;
    for inst in insts {
        let o = inst.operands.clone();
        match Op::from_u32(inst.op as u32) {
            Some(Op::TypeSampler) => {
                // Declared (once) before the first sampled-image type, below.
                if !sampler_declared {
                    out.push(inst);
                    sampler_declared = true;
                }
            }
            Some(Op::TypeSampledImage) => {
                if !sampler_declared {
                    out.push(Inst::new(Op::TypeSampler, vec![sampler_type]));
                    sampler_declared = true;
                }
                out.push(inst);
            }
            Some(Op::TypeArray | Op::TypeRuntimeArray) if arrays.contains_key(&o[0]) => {
                let mut image = o.clone();
                image[1] = image_of(o[1]);
                let mut sampler = o.clone();
                sampler[0] = arrays[&o[0]];
                sampler[1] = sampler_of(o[1]);
                out.push(Inst {
                    op: inst.op,
                    operands: image,
                });
                out.push(Inst {
                    op: inst.op,
                    operands: sampler,
                });
            }
            Some(Op::TypePointer) if pointers.contains_key(&o[0]) => {
                out.push(Inst::new(Op::TypePointer, vec![o[0], o[1], image_of(o[2])]));
                out.push(Inst::new(
                    Op::TypePointer,
                    vec![pointers[&o[0]], o[1], sampler_of(o[2])],
                ));
            }
            Some(Op::TypeFunction) => {
                let mut operands = vec![o[0], o[1]];
                for &p in &o[2..] {
                    operands.push(p);
                    if let Some(&twin) = pointers.get(&p) {
                        operands.push(twin);
                    }
                }
                out.push(Inst::new(Op::TypeFunction, operands));
            }
            Some(Op::Variable) if twins.contains_key(&o[1]) => {
                let mut sampler = o.clone();
                sampler[0] = pointers[&o[0]];
                sampler[1] = twins[&o[1]];
                out.push(inst);
                out.push(Inst::new(Op::Variable, sampler));
            }
            Some(Op::Decorate) if o.len() >= 3 && o[1] == BINDING && twins.contains_key(&o[0]) => {
                out.push(inst);
                if let Some(&(group, binding)) = sampler_binding.get(&o[0]) {
                    let twin = twins[&o[0]];
                    out.push(Inst::new(Op::Decorate, vec![twin, DESCRIPTOR_SET, group]));
                    out.push(Inst::new(Op::Decorate, vec![twin, BINDING, binding]));
                }
            }
            Some(Op::Name) if twins.contains_key(&o[0]) && vars.contains(&o[0]) => {
                let mut operands = vec![twins[&o[0]]];
                operands.extend(string_words(&format!("{}_sampler", string_of(&o[1..]))));
                out.push(inst);
                out.push(Inst::new(Op::Name, operands));
            }
            Some(Op::FunctionParameter) if pointers.contains_key(&o[0]) => {
                let twin = fresh();
                twins.insert(o[1], twin);
                out.push(inst);
                out.push(Inst::new(
                    Op::FunctionParameter,
                    vec![pointers[&o[0]], twin],
                ));
            }
            Some(Op::AccessChain | Op::InBoundsAccessChain) if twins.contains_key(&o[2]) => {
                let twin_type = *pointers
                    .get(&o[0])
                    .ok_or("an access chain into a combined image sampler of an unknown type")?;
                let twin = fresh();
                let mut sampler = o.clone();
                sampler[0] = twin_type;
                sampler[1] = twin;
                sampler[2] = twins[&o[2]];
                twins.insert(o[1], twin);
                out.push(inst.clone());
                out.push(Inst {
                    op: inst.op,
                    operands: sampler,
                });
            }
            Some(Op::Load) if twins.contains_key(&o[2]) => {
                if !sampled.contains_key(&o[0]) {
                    return Err("a whole array of combined image samplers is loaded".into());
                }
                let (image, sampler) = (fresh(), fresh());
                let mut load_image = o.clone();
                load_image[0] = image_of(o[0]);
                load_image[1] = image;
                out.push(Inst::new(Op::Load, load_image));
                out.push(Inst::new(
                    Op::Load,
                    vec![sampler_type, sampler, twins[&o[2]]],
                ));
                out.push(Inst::new(
                    Op::SampledImage,
                    vec![o[0], o[1], image, sampler],
                ));
            }
            Some(Op::FunctionCall) => {
                let mut operands = o[..3].to_vec();
                for &arg in &o[3..] {
                    operands.push(arg);
                    if let Some(&twin) = twins.get(&arg) {
                        operands.push(twin);
                    }
                }
                out.push(Inst::new(Op::FunctionCall, operands));
            }
            _ => out.push(inst),
        }
    }
    header[3] = next_id;
    Ok((encode(&header, &out), split))
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
