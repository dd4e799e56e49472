//! What text an expression of glslang's SPIR-V is written as in GLSL: the operator, function,
//! constructor, member, variable or literal a line's parse must hold for the value to be there.

use naga::{BinaryOperator as B, Expression, Handle, MathFunction as M, UnaryOperator as U};

use super::{Forest, Kind};

/// One function with its module and the validator's types.
pub(super) struct Ctx<'a> {
    pub(super) module: &'a naga::Module,
    pub(super) fun: &'a naga::Function,
    pub(super) info: &'a naga::valid::FunctionInfo,
}

/// What text an expression is written as.
#[derive(Debug)]
pub(super) enum Want {
    /// A binary operator (or its compound assignment).
    Binary(&'static [&'static str]),
    Unary(&'static str),
    /// A call to one of these names.
    Call(Vec<String>),
    /// A call whose name starts with this (`texture…`).
    CallPrefix(&'static str),
    /// A constructor: a call named by a type.
    Constructor,
    /// `.name` (one of the names).
    Member(Vec<String>),
    /// `[…]`.
    Index,
    /// A variable: `name`, or a block's member read without the block's name.
    Variable(String),
    Number(f64),
    Ternary,
}

impl Want {
    pub(super) fn accepts(&self, forest: &Forest, n: usize) -> bool {
        let node = &forest.nodes[n];
        match (self, &node.kind) {
            (Want::Binary(ops), Kind::Binary(op) | Kind::Assign(op)) => ops.contains(op),
            (Want::Unary(want), Kind::Unary(op)) => want == op,
            (Want::Call(names), Kind::Call(name)) => names.iter().any(|n| n == name),
            (Want::CallPrefix(prefix), Kind::Call(name)) => name.starts_with(prefix),
            (Want::Constructor, Kind::Call(name)) => is_type_name(name),
            (Want::Member(names), Kind::Member(name)) => names.iter().any(|n| n == name),
            (Want::Index, Kind::Index) => true,
            (Want::Variable(want), Kind::Ident(name)) => want == name,
            (Want::Number(want), Kind::Number(v)) => {
                (want - v).abs() <= 1e-6 * want.abs().max(v.abs()).max(1e-30)
            }
            (Want::Ternary, Kind::Ternary) => true,
            _ => false,
        }
    }

    /// A variable or a literal: written as one token, placed where its user is.
    pub(super) fn is_leaf(&self) -> bool {
        matches!(self, Want::Variable(_) | Want::Number(_))
    }
}

impl Ctx<'_> {
    /// The type of `h`'s value, past a pointer.
    fn value_type(&self, h: Handle<Expression>) -> Option<naga::TypeInner> {
        let types = &self.module.types;
        Some(match *self.info[h].ty.inner_with(types) {
            naga::TypeInner::Pointer { base, .. } => types[base].inner.clone(),
            naga::TypeInner::ValuePointer {
                size: Some(size),
                scalar,
                ..
            } => naga::TypeInner::Vector { size, scalar },
            naga::TypeInner::ValuePointer { scalar, .. } => naga::TypeInner::Scalar(scalar),
            ref inner => inner.clone(),
        })
    }

    /// Whether `h` is a pointer (never a value written in the text).
    pub(super) fn is_pointer(&self, h: Handle<Expression>) -> bool {
        matches!(
            self.info[h].ty.inner_with(&self.module.types),
            naga::TypeInner::Pointer { .. } | naga::TypeInner::ValuePointer { .. }
        )
    }

    /// The text `h` is written as, where it has any.
    pub(super) fn wanted(&self, h: Handle<Expression>) -> Option<Want> {
        let fun = self.fun;
        Some(match fun.expressions[h] {
            Expression::Binary { op, .. } => Want::Binary(binary_texts(op)),
            Expression::Unary { op, .. } => Want::Unary(match op {
                U::Negate => "-",
                U::LogicalNot => "!",
                U::BitwiseNot => "~",
            }),
            Expression::Math { fun: f, .. } => Want::Call(math_names(f)),
            Expression::Relational { fun: f, .. } => Want::Call(vec![
                match f {
                    naga::RelationalFunction::All => "all",
                    naga::RelationalFunction::Any => "any",
                    naga::RelationalFunction::IsNan => "isnan",
                    naga::RelationalFunction::IsInf => "isinf",
                }
                .to_owned(),
            ]),
            Expression::Derivative { axis, ctrl, .. } => {
                use naga::{DerivativeAxis as A, DerivativeControl as C};
                let base = match axis {
                    A::X => "dFdx",
                    A::Y => "dFdy",
                    A::Width => "fwidth",
                };
                let suffix = match ctrl {
                    C::Coarse => "Coarse",
                    C::Fine => "Fine",
                    C::None => "",
                };
                Want::Call(vec![format!("{base}{suffix}")])
            }
            Expression::ImageSample { .. } => Want::CallPrefix("texture"),
            Expression::ImageLoad { .. } => {
                Want::Call(vec!["texelFetch".into(), "imageLoad".into()])
            }
            Expression::Compose { .. } | Expression::Splat { .. } | Expression::As { .. } => {
                Want::Constructor
            }
            Expression::Swizzle { size, pattern, .. } => {
                Want::Member(swizzle_names(&pattern[..size as usize]))
            }
            Expression::AccessIndex { base, index } => self.member(base, index),
            Expression::Access { base, index } => match self.constant_index(index) {
                Some(i) => self.member(base, i),
                None => Want::Index,
            },
            Expression::Select { .. } => Want::Ternary,
            Expression::Literal(l) => Want::Number(literal_value(l)?),
            Expression::Constant(c) => {
                let constant = &self.module.constants[c];
                match (
                    &constant.name,
                    &self.module.global_expressions[constant.init],
                ) {
                    (Some(name), _) if !name.is_empty() => Want::Variable(name.clone()),
                    (_, Expression::Literal(l)) => Want::Number(literal_value(*l)?),
                    _ => return None,
                }
            }
            Expression::FunctionArgument(i) => Want::Variable(self.argument(i)?),
            Expression::Load { pointer } => return self.loaded(pointer),
            Expression::CallResult(f) => Want::Call(vec![self.module.functions[f].name.clone()?]),
            _ => return None,
        })
    }

    fn argument(&self, i: u32) -> Option<String> {
        self.fun.arguments.get(i as usize)?.name.clone()
    }

    fn global_name(&self, g: Handle<naga::GlobalVariable>) -> Option<String> {
        self.module.global_variables[g]
            .name
            .clone()
            .filter(|n| !n.is_empty())
    }

    /// A load: of a named variable (`name`), or of a member.
    pub(super) fn loaded(&self, pointer: Handle<Expression>) -> Option<Want> {
        let fun = self.fun;
        match fun.expressions[pointer] {
            Expression::LocalVariable(v) => {
                Some(Want::Variable(fun.local_variables[v].name.clone()?))
            }
            Expression::GlobalVariable(g) => Some(Want::Variable(self.global_name(g)?)),
            Expression::FunctionArgument(i) => Some(Want::Variable(self.argument(i)?)),
            // `p.x` read through a pointer: the member.
            Expression::AccessIndex { base, index } => Some(self.member(base, index)),
            Expression::Access { base, index } => Some(match self.constant_index(index) {
                Some(i) => self.member(base, i),
                None => Want::Index,
            }),
            _ => None,
        }
    }

    /// Member `index` of `base`: `.name` (a struct member, a vector component), or a member of
    /// an unnamed block read by its own name, or `[index]` (arrays, matrices).
    fn member(&self, base: Handle<Expression>, index: u32) -> Want {
        let unnamed_block = match self.fun.expressions[base] {
            Expression::GlobalVariable(g) => self.global_name(g).is_none(),
            _ => false,
        };
        match (unnamed_block, self.member_names(base, index)) {
            (true, Some(mut n)) => Want::Variable(n.swap_remove(0)),
            (false, Some(n)) => Want::Member(n),
            (_, None) => Want::Index,
        }
    }

    /// The names `.index` of `base` is written with: a struct member's name, or a vector
    /// component's letters; none for arrays and matrices.
    fn member_names(&self, base: Handle<Expression>, index: u32) -> Option<Vec<String>> {
        match self.value_type(base)? {
            naga::TypeInner::Struct { ref members, .. } => {
                Some(vec![members.get(index as usize)?.name.clone()?])
            }
            naga::TypeInner::Vector { .. } => {
                let i = index as usize;
                Some(
                    ["xyzw", "rgba", "stpq"]
                        .iter()
                        .filter_map(|set| set.get(i..i + 1).map(str::to_owned))
                        .collect(),
                )
            }
            _ => None,
        }
    }

    /// The value of an index that is a constant (glslang's `OpAccessChain` indexes by
    /// constants).
    fn constant_index(&self, index: Handle<Expression>) -> Option<u32> {
        let v = match self.fun.expressions[index] {
            Expression::Literal(l) => literal_value(l)?,
            Expression::Constant(c) => {
                match self.module.global_expressions[self.module.constants[c].init] {
                    Expression::Literal(l) => literal_value(l)?,
                    _ => return None,
                }
            }
            _ => return None,
        };
        (v >= 0.0 && v.fract() == 0.0 && v <= f64::from(u32::MAX)).then_some(v as u32)
    }
}

fn swizzle_names(pattern: &[naga::SwizzleComponent]) -> Vec<String> {
    ["xyzw", "rgba", "stpq"]
        .iter()
        .map(|set| {
            pattern
                .iter()
                .map(|c| set.as_bytes()[*c as usize] as char)
                .collect()
        })
        .collect()
}

fn binary_texts(op: B) -> &'static [&'static str] {
    match op {
        B::Add => &["+", "+="],
        B::Subtract => &["-", "-="],
        B::Multiply => &["*", "*="],
        B::Divide => &["/", "/="],
        B::Modulo => &["%", "%="],
        B::Equal => &["=="],
        B::NotEqual => &["!="],
        B::Less => &["<"],
        B::LessEqual => &["<="],
        B::Greater => &[">"],
        B::GreaterEqual => &[">="],
        B::And => &["&", "&="],
        B::ExclusiveOr => &["^", "^="],
        B::InclusiveOr => &["|", "|="],
        B::LogicalAnd => &["&&"],
        B::LogicalOr => &["||"],
        B::ShiftLeft => &["<<", "<<="],
        B::ShiftRight => &[">>", ">>="],
    }
}

/// GLSL's names for a math function (naga's name, lower case, where GLSL spells it so).
fn math_names(f: M) -> Vec<String> {
    let named: &[&str] = match f {
        M::Atan2 => &["atan"],
        M::Outer => &["outerProduct"],
        M::Round => &["round", "roundEven"],
        M::Saturate => &["clamp"],
        M::Fma => &["fma"],
        M::CountOneBits => &["bitCount"],
        M::ReverseBits => &["bitfieldReverse"],
        M::ExtractBits => &["bitfieldExtract"],
        M::InsertBits => &["bitfieldInsert"],
        M::FirstTrailingBit => &["findLSB"],
        M::FirstLeadingBit => &["findMSB"],
        _ => &[],
    };
    if named.is_empty() {
        vec![format!("{f:?}").to_lowercase()]
    } else {
        named.iter().map(|s| (*s).to_owned()).collect()
    }
}

fn literal_value(l: naga::Literal) -> Option<f64> {
    Some(match l {
        naga::Literal::F32(v) => v as f64,
        naga::Literal::F16(v) => f64::from(v),
        naga::Literal::F64(v) => v,
        naga::Literal::I32(v) => v as f64,
        naga::Literal::U32(v) => v as f64,
        naga::Literal::I64(v) => v as f64,
        naga::Literal::U64(v) => v as f64,
        naga::Literal::AbstractInt(v) => v as f64,
        naga::Literal::AbstractFloat(v) => v,
        naga::Literal::U16(v) => f64::from(v),
        naga::Literal::I16(v) => f64::from(v),
        naga::Literal::Bool(_) => return None,
    })
}

/// A type's name in GLSL: a constructor call is named by one (or by a struct, capitalized by
/// habit; a lower-case function of the shader's own is a [`Want::Call`] of its name instead).
fn is_type_name(name: &str) -> bool {
    let prefix = name.trim_start_matches(['i', 'u', 'b', 'd', 'f']);
    matches!(name, "float" | "int" | "uint" | "bool" | "double")
        || prefix.starts_with("vec")
        || prefix.starts_with("mat")
        || name.starts_with("float16_t")
        || name.starts_with("f16vec")
        || name.chars().next().is_some_and(|c| c.is_ascii_uppercase())
}
