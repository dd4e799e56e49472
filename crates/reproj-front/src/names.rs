//! naga_oil's decorated names made readable for messages. A composed shader's imported items are
//! named `itemX_naga_oil_mod_X<module path in base32>X` (naga_oil's decoration, which the WGSL
//! reproj writes keeps); [`undecorate`] turns each into `module::item`, as naga_oil's own errors
//! do, without naga_oil (the light build has it not).

use std::borrow::Cow;

const PRE: &str = "X_naga_oil_mod_X";

/// `text` with every decorated name as `module::item` (unchanged where there is none, or where a
/// decoration does not decode).
pub fn undecorate(text: &str) -> Cow<'_, str> {
    if !text.contains(PRE) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find(PRE) {
        // The item: the identifier characters just before the decoration.
        let head = &rest[..at];
        let item_start = head
            .char_indices()
            .rev()
            .take_while(|(_, c)| c.is_alphanumeric() || *c == '_')
            .last()
            .map_or(at, |(i, _)| i);
        let after = &rest[at + PRE.len()..];
        // The module: the run of base32 letters and digits, less the closing `X`.
        let run = after
            .find(|c: char| !(c.is_ascii_uppercase() || c.is_ascii_digit()))
            .unwrap_or(after.len());
        let decoded = (run > 0 && after[..run].ends_with('X'))
            .then(|| base32(&after[..run - 1]))
            .flatten();
        match decoded {
            Some(module) if item_start < at => {
                out.push_str(&head[..item_start]);
                out.push_str(&module);
                out.push_str("::");
                out.push_str(&head[item_start..]);
                rest = &after[run..];
            }
            _ => {
                out.push_str(&rest[..at + PRE.len()]);
                rest = after;
            }
        }
    }
    out.push_str(rest);
    Cow::Owned(out)
}

/// RFC 4648 base32 without padding, as naga_oil encodes module paths; `None` if it is not that
/// or not UTF-8.
fn base32(text: &str) -> Option<String> {
    let mut bits: u64 = 0;
    let mut count = 0;
    let mut bytes = Vec::new();
    for c in text.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'2'..=b'7' => c - b'2' + 26,
            _ => return None,
        };
        bits = (bits << 5) | u64::from(v);
        count += 5;
        if count >= 8 {
            count -= 8;
            bytes.push((bits >> count) as u8);
            bits &= (1 << count) - 1;
        }
    }
    String::from_utf8(bytes).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decorated_names_read_as_module_paths() {
        // naga_oil's decoration of `bevy_pbr::mesh_view_bindings` (base32 of the path).
        let text = "`point_shadow_texturesX_naga_oil_mod_XMJSXM6K7OBRHEOR2NVSXG2C7OZUWK527MJUW4ZDJNZTXGX` (@group(0) @binding(2)): texture `point_shadow_texturesX_naga_oil_mod_XMJSXM6K7OBRHEOR2NVSXG2C7OZUWK527MJUW4ZDJNZTXGX`";
        assert_eq!(
            undecorate(text),
            "`bevy_pbr::mesh_view_bindings::point_shadow_textures` (@group(0) @binding(2)): texture `bevy_pbr::mesh_view_bindings::point_shadow_textures`"
        );
        assert_eq!(undecorate("no decoration"), "no decoration");
        // A decoration that does not decode stays as it is.
        assert_eq!(undecorate("aX_naga_oil_mod_X1X b"), "aX_naga_oil_mod_X1X b");
        assert_eq!(base32("MJSXM6I"), Some("bevy".into()));
    }
}
