//! `raytree diagram` through the binary: SVG and PNG written at the asked size, and bad
//! arguments exit 2 with an error and leave no file.

mod common;
use common::{fixture, raytree};

#[test]
fn cli_writes_svg_and_png() {
    let dir = tempfile::tempdir().unwrap();
    let tir = fixture("tir-block.json");
    for out in ["fig.svg", "fig.png"] {
        let o = raytree(
            &[
                "diagram",
                &tir,
                "--pixel",
                "320,230",
                "-o",
                out,
                "--theme",
                "dark",
                "--size",
                "800x450",
                "--zoom-offsets",
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(dir.path().join(out).metadata().unwrap().len() > 1000);
    }
    let png = image::open(dir.path().join("fig.png")).unwrap();
    assert_eq!((png.width(), png.height()), (800, 450));
}

#[test]
fn cli_errors_exit_2_and_leave_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [&[&str]; 8] = [
        &["diagram", "--pixel", "1,1", "--plane", "w=3", "-o", "a.svg"],
        &[
            "diagram", "--pixel", "1,1", "--plane", "1,2,3", "-o", "a.svg",
        ],
        &["diagram", "--pixel", "640,10", "-o", "a.svg"],
        &["diagram", "--pixel", "1,1", "-o", "missing/dir/a.png"],
        &["diagram", "--pixel", "1,1", "-o", "a.gif"],
        &[
            "diagram", "--pixel", "1,1", "--theme", "pink", "-o", "a.svg",
        ],
        &[
            "diagram",
            "--pixel",
            "1,1",
            "--kinds",
            "camera,laser",
            "-o",
            "a.svg",
        ],
        &["diagram", "--pixel", "1,1", "--sample", "3", "-o", "a.svg"],
    ];
    for args in cases {
        let o = raytree(args, dir.path());
        assert_eq!(
            o.status.code(),
            Some(2),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.starts_with("error: "), "{err}");
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert!(left.is_empty(), "{args:?} left {left:?}");
    }
    let o = raytree(
        &["diagram", "--pixel", "1,1", "--plane", "w=3", "-o", "a.svg"],
        dir.path(),
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("--plane"));
}
