//! Scenes into the page: the demo, a glTF file by URL (its buffers and images fetched
//! beside it) or dropped files, and a settings file by URL. Errors name the file.

use super::dom::{fetch_bytes, fetch_text};
use crate::dropped::{dropped_path, match_wanted, scene_file};
use chiaro_scene::demo::{DEMO_LOCAL_LIGHTS, DEMO_SHADOWED_POINTS, DEMO_SHADOWED_SPOTS, demo_scene_in_studio};
use chiaro_scene::{GivenFiles, Scene, Settings, load_gltf_given, referenced_files};
use std::path::{Path, PathBuf};

/// The built-in demo as `chiaro render` makes it without a file.
pub fn demo() -> Scene {
    demo_scene_in_studio(DEMO_LOCAL_LIGHTS, DEMO_SHADOWED_SPOTS, DEMO_SHADOWED_POINTS)
}

/// The glTF file at `url` (relative to the page) with the files it names beside it. A
/// file that cannot be fetched is left out and the loader names it, if it needs it.
pub async fn scene_from_url(url: &str) -> Result<Scene, String> {
    let bytes = fetch_bytes(url).await?;
    let path = PathBuf::from(url.split(['?', '#']).next().unwrap_or(url));
    let mut files = GivenFiles::new();
    for wanted in referenced_files(&path, &bytes).map_err(|e| e.to_string())? {
        let file_url = fetch_url(&wanted);
        match fetch_bytes(&file_url).await {
            Ok(data) => {
                files.insert(wanted, data);
            }
            Err(e) => web_sys::console::warn_1(&e.into()),
        }
    }
    load(&path, &bytes, &files)
}

/// `path` (a URI decoded and joined to the scene's folder) as a URL again: the characters
/// a URL reads as its query, fragment or an escape are escaped (a file named "a#1.png").
fn fetch_url(path: &Path) -> String {
    const SPECIAL: &percent_encoding::AsciiSet = &percent_encoding::CONTROLS.add(b'%').add(b'#').add(b'?');
    percent_encoding::utf8_percent_encode(&path.to_string_lossy(), SPECIAL).to_string()
}

/// The scene among dropped files (`names[i]` with `contents[i]`), with its files.
pub fn scene_from_dropped(names: &[String], contents: &[Vec<u8>]) -> Result<Scene, String> {
    let index = scene_file(names)?;
    let path = dropped_path(&names[index]);
    let wanted = referenced_files(&path, &contents[index]).map_err(|e| e.to_string())?;
    let files: GivenFiles = match_wanted(&wanted, names).into_iter().map(|(p, i)| (p, contents[i].clone())).collect();
    load(&path, &contents[index], &files)
}

fn load(path: &Path, bytes: &[u8], files: &GivenFiles) -> Result<Scene, String> {
    let scene = load_gltf_given(path, bytes, files).map_err(|e| e.to_string())?;
    for reason in &scene.ignored {
        web_sys::console::info_1(&format!("{}: ignored {reason}", path.display()).into());
    }
    Ok(scene)
}

/// The settings file at `url`, or the defaults.
pub async fn settings(url: Option<&str>) -> Result<Settings, String> {
    match url {
        Some(url) => {
            let text = fetch_text(url).await?;
            Settings::parse(&text).map_err(|e| format!("{url}: {e}"))
        }
        None => Ok(Settings::default()),
    }
}

/// `scene` in the settings' material variant, as `chiaro render` picks it.
pub fn with_variant(mut scene: Scene, settings: &Settings) -> Result<Scene, String> {
    if let Some(name) = settings.scene.variant.as_deref() {
        scene.select_variant(Some(name)).map_err(|e| e.to_string())?;
    }
    Ok(scene)
}
