//! Debug helper: print the WGSL round trip of a file, three times.
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let mut text = std::fs::read_to_string(&path).unwrap();
    for i in 0..3 {
        let m = naga::front::wgsl::parse_str(&text)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&text)));
        let info = reproj_front::validator().validate(&m).unwrap();
        let out = naga::back::wgsl::write_string(&m, &info, naga::back::wgsl::WriterFlags::empty())
            .unwrap();
        std::fs::write(format!("/tmp/rt{i}.wgsl"), &out).unwrap();
        text = out;
    }
}
