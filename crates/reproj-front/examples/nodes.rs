//! Debug helper: print the normalized WGSL and the node table of a shader.
fn main() {
    let path = std::env::args().nth(1).expect("usage: nodes FILE");
    let shader =
        reproj_front::load_file(std::path::Path::new(&path)).unwrap_or_else(|e| panic!("{e}"));
    let norm =
        reproj_front::normalize(&shader, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    let wgsl = naga::back::wgsl::write_string(
        &norm.module,
        &norm.info,
        naga::back::wgsl::WriterFlags::empty(),
    )
    .unwrap();
    println!("{wgsl}");
    let table = reproj_front::enumerate(&shader, &norm);
    for n in &table.nodes {
        println!(
            "{:4} {:6} {:20} {:>8.1} {:>8.1} {:3}:{:<3} {}",
            n.id,
            n.cacheable,
            n.reason.map(|r| r.as_str()).unwrap_or(""),
            n.cost,
            n.overlap,
            n.line,
            n.col,
            n.text
        );
    }
}
