//! A session's sampler as wgpu takes it.

use reproj_scene::session::{Address, Compare, Filter, SamplerSpec, Session};

/// The sampler the session specifies for `name`, as wgpu takes it: an unlisted sampler is the
/// session's default, an unlisted comparison sampler clamps; anisotropy only where every filter
/// is linear (wgpu's rule).
pub fn sampler_descriptor<'a>(
    session: &Session,
    name: &'a str,
    comparison: bool,
) -> wgpu::SamplerDescriptor<'a> {
    let spec = session
        .samplers
        .get(name)
        .cloned()
        .unwrap_or(if comparison {
            SamplerSpec {
                address: Address::Clamp,
                ..Default::default()
            }
        } else {
            SamplerSpec::default()
        });
    let compare = comparison.then(|| match spec.compare.unwrap_or_default() {
        Compare::Never => wgpu::CompareFunction::Never,
        Compare::Less => wgpu::CompareFunction::Less,
        Compare::Equal => wgpu::CompareFunction::Equal,
        Compare::LessEqual => wgpu::CompareFunction::LessEqual,
        Compare::Greater => wgpu::CompareFunction::Greater,
        Compare::NotEqual => wgpu::CompareFunction::NotEqual,
        Compare::GreaterEqual => wgpu::CompareFunction::GreaterEqual,
        Compare::Always => wgpu::CompareFunction::Always,
    });
    let filter = |x: Filter| match x {
        Filter::Linear => wgpu::FilterMode::Linear,
        Filter::Nearest => wgpu::FilterMode::Nearest,
    };
    let address = match spec.address {
        Address::Repeat => wgpu::AddressMode::Repeat,
        Address::Clamp => wgpu::AddressMode::ClampToEdge,
        Address::Mirror => wgpu::AddressMode::MirrorRepeat,
    };
    let all_linear = spec.filter == Filter::Linear && spec.mipmap_filter == Filter::Linear;
    wgpu::SamplerDescriptor {
        label: Some(name),
        address_mode_u: address,
        address_mode_v: address,
        address_mode_w: address,
        mag_filter: filter(spec.filter),
        min_filter: filter(spec.filter),
        mipmap_filter: match spec.mipmap_filter {
            Filter::Linear => wgpu::MipmapFilterMode::Linear,
            Filter::Nearest => wgpu::MipmapFilterMode::Nearest,
        },
        anisotropy_clamp: if all_linear { spec.anisotropy } else { 1 },
        compare,
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The marble session with `samplers` added.
    fn session(samplers: &[(&str, SamplerSpec)]) -> Session {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../sessions/marble.json");
        let mut s = Session::load(path).unwrap();
        for (name, spec) in samplers {
            s.samplers.insert((*name).to_owned(), spec.clone());
        }
        s
    }

    #[test]
    fn an_unlisted_comparison_sampler_clamps_and_compares() {
        let s = session(&[]);
        let d = sampler_descriptor(&s, "shadow", true);
        assert_eq!(d.address_mode_u, wgpu::AddressMode::ClampToEdge);
        assert!(d.compare.is_some());
        let d = sampler_descriptor(&s, "plain", false);
        assert_eq!(d.compare, None);
    }

    #[test]
    fn anisotropy_only_where_every_filter_is_linear() {
        let linear = SamplerSpec {
            filter: Filter::Linear,
            mipmap_filter: Filter::Linear,
            anisotropy: 8,
            ..Default::default()
        };
        let nearest = SamplerSpec {
            filter: Filter::Nearest,
            ..linear.clone()
        };
        let s = session(&[("a", linear), ("b", nearest)]);
        assert_eq!(sampler_descriptor(&s, "a", false).anisotropy_clamp, 8);
        assert_eq!(sampler_descriptor(&s, "b", false).anisotropy_clamp, 1);
        assert_eq!(
            sampler_descriptor(&s, "b", false).mag_filter,
            wgpu::FilterMode::Nearest
        );
    }
}
