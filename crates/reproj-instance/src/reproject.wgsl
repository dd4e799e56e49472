// reproj pass 1 (three-pass strategy): keep the payload on a hit, discard anything else.

@fragment
fn fs_main(REPROJ_ENTRY_INPUT) -> @location(0) vec4<f32> {
    REPROJ_MAKE_INPUT
    // A refreshed block needs no lookup at all.
    if reproj_refreshed(in.position.xy) {
        discard;
    }
    let r = reproj_lookup(in);
    if r.status != 0u {
        discard;
    }
    return r.payload;
}

