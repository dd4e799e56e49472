//! The session motion measured from geometry and camera: zero when nothing moves, larger for a
//! faster orbit, and in proportion.

use std::path::PathBuf;

use reproj_emit::motion::measure;
use reproj_scene::Session;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn a_static_session_does_not_move_and_a_faster_orbit_moves_faster() {
    let still = Session::load(root().join("sessions/test_static.json")).unwrap();
    let m = measure(&still, None).unwrap();
    assert!(m.pixels_per_frame < 1e-3, "{m:?}");
    assert!(m.view_deg_per_frame < 1e-3, "{m:?}");

    let slow = measure(
        &Session::load(root().join("sessions/marble.json")).unwrap(),
        None,
    )
    .unwrap();
    let fast = measure(
        &Session::load(root().join("sessions/marble_fast.json")).unwrap(),
        None,
    )
    .unwrap();
    assert!(slow.check().is_ok() && fast.check().is_ok());
    assert_eq!(slow.per_frame.len(), 150);
    assert!(slow.pixels_per_frame > 0.05, "{slow:?}");
    // The fast session orbits 160° where the slow one orbits 40° over as many frames (and the
    // torus turns alike in both): between 1.5 and 4 times the screen motion.
    let ratio = fast.pixels_per_frame / slow.pixels_per_frame;
    assert!((1.5..=4.0).contains(&ratio), "{ratio}: {slow:?} {fast:?}");
    assert!(fast.view_deg_per_frame > slow.view_deg_per_frame);
    // Fewer frames: the motion over those.
    let first = measure(
        &Session::load(root().join("sessions/marble.json")).unwrap(),
        Some(10),
    )
    .unwrap();
    assert_eq!(first.per_frame.len(), 10);
}
