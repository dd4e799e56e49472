//! Cleanup after the writers: frames written on other threads while a signal's cleanup runs
//! must not bring the staged directory back. Its own test binary: cleanup closes the whole
//! process to writes, which would fail any test running beside it.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use reproj_io::{Replace, StagedDir, WriteError};

#[test]
fn nothing_is_created_once_cleanup_has_started() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("frames");
    let staged = StagedDir::new(&out, Replace::OwnFiles(&["png"])).unwrap();
    let stage = staged.path().to_owned();
    let written = Arc::new(AtomicUsize::new(0));
    // Four writers, as frame writers: each writes files into the staging directory until it is
    // refused (`write_file` creates the directory again if it is missing: the race).
    let writers: Vec<_> = (0..4)
        .map(|t| {
            let (stage, written) = (stage.clone(), Arc::clone(&written));
            std::thread::spawn(move || {
                for n in 0.. {
                    let path = stage.join(format!("frame_{t}_{n}.png"));
                    match reproj_io::write_file(&path, &[0u8; 4096]) {
                        Ok(()) => written.fetch_add(1, Ordering::Relaxed),
                        Err(e) => return e,
                    };
                }
                unreachable!()
            })
        })
        .collect();
    while written.load(Ordering::Relaxed) < 40 {
        std::thread::yield_now();
    }
    assert!(!reproj_io::cleanup_started());
    // What the SIGINT handler does, on its own thread.
    reproj_io::remove_registered();
    assert!(reproj_io::cleanup_started());
    assert!(
        !stage.exists(),
        "the staged directory is gone as soon as cleanup returns"
    );
    for w in writers {
        let e = w.join().unwrap();
        assert!(matches!(e, WriteError::Interrupted { .. }), "{e}");
        assert!(e.to_string().contains("interrupted"), "{e}");
    }
    assert!(!stage.exists(), "no writer created it again");
    // Every writer refuses from now on, and creates nothing.
    let e = reproj_io::write_file(&stage.join("late.png"), b"x").unwrap_err();
    assert!(matches!(e, WriteError::Interrupted { .. }), "{e}");
    assert!(matches!(
        staged.write("late2.png", b"x").unwrap_err(),
        WriteError::Interrupted { .. }
    ));
    assert!(matches!(
        StagedDir::new(&dir.path().join("other"), Replace::OwnFiles(&["png"])).unwrap_err(),
        WriteError::Interrupted { .. }
    ));
    assert!(matches!(
        reproj_io::OutputLock::acquire(&dir.path().join("p.json")).unwrap_err(),
        WriteError::Interrupted { .. }
    ));
    assert!(staged.commit().is_err());
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}
