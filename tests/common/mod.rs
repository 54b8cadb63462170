//! Helpers shared by the integration tests (each `tests/*.rs` is its own crate, and none uses
//! every helper).
#![allow(dead_code)]

pub mod stats;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Run the `raytree` binary with `args` in `dir`.
pub fn raytree(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raytree"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the raytree binary runs")
}

/// The path of `fixtures/NAME`, as an argument for the binary.
pub fn fixture(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name)
        .display()
        .to_string()
}

/// The process's standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Assert exit code 2 and return stderr.
pub fn fails(o: &Output) -> String {
    assert_eq!(
        o.status.code(),
        Some(2),
        "stdout: {}\nstderr: {}",
        String::from_utf8_lossy(&o.stdout),
        stderr(o)
    );
    stderr(o)
}

/// `raytree args` in `dir` exits 2 with `text` in its error and leaves no file in `dir` besides
/// the scene `s.json`.
pub fn fails_with(dir: &Path, args: &[&str], text: &str) {
    let o = raytree(args, dir);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert!(err.contains(text), "{args:?}: {err}");
    let written: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name() != "s.json")
        .collect();
    assert!(written.is_empty(), "{args:?} wrote {written:?}");
}

/// SplitMix64: deterministic numbers for the seeded test loops.
pub struct Rng(pub u64);

impl Rng {
    /// The next number in `[0, 1)`.
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The fixture as a GLB: its data-URI buffer moved into the BIN chunk.
pub fn fixture_glb() -> Vec<u8> {
    let text = std::fs::read_to_string(fixture("formats/cornell-box.gltf")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let uri = v["buffers"][0]["uri"].as_str().unwrap().to_string();
    let bin = decode_base64(uri.split_once(',').unwrap().1);
    v["buffers"][0].as_object_mut().unwrap().remove("uri");
    glb(&v, &bin)
}

pub fn decode_base64(s: &str) -> Vec<u8> {
    let val = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        _ => 63,
    };
    let s: Vec<u8> = s.bytes().filter(|&c| c != b'=').collect();
    let mut out = Vec::new();
    for c in s.chunks(4) {
        let n = c
            .iter()
            .enumerate()
            .fold(0u32, |a, (k, &x)| a | u32::from(val(x)) << (18 - 6 * k));
        for k in 0..c.len() - 1 {
            out.push((n >> (16 - 8 * k)) as u8);
        }
    }
    out
}

pub fn glb(json: &serde_json::Value, bin: &[u8]) -> Vec<u8> {
    let mut j = json.to_string().into_bytes();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(((28 + j.len() + b.len()) as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((b.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(b);
    out
}
