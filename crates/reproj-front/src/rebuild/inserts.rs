//! Expressions a rewrite puts in place of the source's: a cached value read back (texture or
//! argument), a constant (code simplification), and the payload returned after a stop.

use super::*;

impl Out<'_, '_> {
    pub(super) fn cache_read(
        &mut self,
        slot: Slot,
        source: CacheSource,
        span: Span,
    ) -> Handle<Expression> {
        use naga::{Expression as E, SwizzleComponent as S};
        let texel = match source {
            CacheSource::Texture { image, position } => self.texture_read(image, position, span),
            CacheSource::Argument(i) => self.append(E::FunctionArgument(i), span),
        };
        let at = |i: u32| [S::X, S::Y, S::Z, S::W][((slot.offset + i) % 4) as usize];
        let size = match slot.components {
            1 => {
                return self.append(
                    E::AccessIndex {
                        base: texel,
                        index: slot.offset,
                    },
                    span,
                );
            }
            4 if slot.offset == 0 => return texel,
            2 => naga::VectorSize::Bi,
            3 => naga::VectorSize::Tri,
            _ => naga::VectorSize::Quad,
        };
        self.append(
            E::Swizzle {
                size,
                vector: texel,
                pattern: [at(0), at(1), at(2), at(3)],
            },
            span,
        )
    }

    pub(super) fn constant(&mut self, c: &Constant, span: Span) -> Handle<Expression> {
        let n = c.components.clamp(1, 4) as usize;
        let literals: Vec<_> = c.value[..n]
            .iter()
            .map(|&v| self.append(Expression::Literal(naga::Literal::F32(v)), span))
            .collect();
        match c.vector {
            Some(ty) if n > 1 => self.append(
                Expression::Compose {
                    ty,
                    components: literals,
                },
                span,
            ),
            _ => literals[0],
        }
    }

    pub(super) fn texture_read(
        &mut self,
        image: Handle<naga::GlobalVariable>,
        position: (u32, Option<u32>),
        span: Span,
    ) -> Handle<Expression> {
        use naga::{Expression as E, SwizzleComponent as S};
        let image = self.append(E::GlobalVariable(image), span);
        let arg = self.append(E::FunctionArgument(position.0), span);
        let pos = match position.1 {
            Some(m) => self.append(
                E::AccessIndex {
                    base: arg,
                    index: m,
                },
                span,
            ),
            None => arg,
        };
        let xy = self.append(
            E::Swizzle {
                size: naga::VectorSize::Bi,
                vector: pos,
                pattern: [S::X, S::Y, S::X, S::X],
            },
            span,
        );
        let coord = self.append(
            E::As {
                expr: xy,
                kind: naga::ScalarKind::Sint,
                convert: Some(4),
            },
            span,
        );
        let level = self.append(E::Literal(naga::Literal::I32(0)), span);
        self.append(
            E::ImageLoad {
                image,
                coordinate: coord,
                array_index: None,
                sample: None,
                level: Some(level),
            },
            span,
        )
    }

    pub(super) fn payload_return(
        &mut self,
        stop: &StopAfter,
        values: &[Handle<Expression>],
        span: Span,
    ) {
        let used: u32 = stop.slots.iter().map(|s| s.components).sum();
        let v = match (values, used) {
            (&[value], 4) => value,
            _ => {
                let mut comps = values.to_vec();
                for _ in used..4 {
                    comps.push(self.append(Expression::Literal(naga::Literal::F32(0.0)), span));
                }
                self.append(
                    Expression::Compose {
                        ty: stop.vec4,
                        components: comps,
                    },
                    span,
                )
            }
        };
        if self.depth == 0 {
            self.root = Some(v);
        }
        self.push_stmt(Statement::Return { value: Some(v) }, span);
    }
}
