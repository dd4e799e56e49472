//! Parse and validate WGSL files with the front end: `cargo run -p reproj-front --example validate -- FILE...`
fn main() {
    let mut failed = false;
    for arg in std::env::args().skip(1) {
        match reproj_front::load_file(std::path::Path::new(&arg)) {
            Ok(_) => println!("{arg}: ok"),
            Err(e) => {
                eprintln!("{e}");
                failed = true;
            }
        }
    }
    std::process::exit(i32::from(failed));
}
