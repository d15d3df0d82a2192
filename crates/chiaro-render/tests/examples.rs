//! The library's examples run as their comments say: `render_png` writes a lit PNG of the
//! demo scene, and `into_texture` renders into a texture on its own device and reads it
//! back. (`cargo test` builds the examples beside the test binaries.)

use std::path::PathBuf;
use std::process::Command;

fn example(name: &str) -> PathBuf {
    let deps = std::env::current_exe().unwrap().parent().unwrap().to_path_buf();
    let path = deps.parent().unwrap().join("examples").join(name);
    assert!(path.exists(), "{} was not built", path.display());
    path
}

#[test]
fn render_png_writes_the_demo_scene() {
    let dir = tempfile_dir();
    // Without arguments, the demo scene to render_png.png.
    let run = Command::new(example("render_png")).current_dir(&dir).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let image = image::open(dir.join("render_png.png")).unwrap().to_rgb8();
    assert_eq!(image.dimensions(), (640, 360));
    let lit = image.pixels().filter(|p| p.0.iter().any(|&c| c > 16)).count();
    assert!(lit > 640 * 360 / 2, "the floor and objects are lit: {lit} pixels");
}

#[test]
fn into_texture_renders_on_the_callers_device() {
    let run = Command::new(example("into_texture")).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let stdout = String::from_utf8_lossy(&run.stdout);
    let lit: u32 = stdout.split("; ").nth(1).and_then(|s| s.split(' ').next()).and_then(|n| n.parse().ok()).unwrap();
    assert!(lit > 256 * 256 / 2, "{stdout}");
}

fn tempfile_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("chiaro-examples-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
