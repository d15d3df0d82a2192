//! Files dropped on the page (or opened with its file button): which one is the scene, and
//! which dropped file each of its external buffers and images is. The browser gives names
//! without folders, so a file the document names under a folder ("textures/a.png") is
//! matched by its name.

use std::path::{Path, PathBuf};

/// The dropped scene: the one `.gltf` or `.glb` among `names`, by index.
pub fn scene_file(names: &[String]) -> Result<usize, String> {
    let scenes: Vec<usize> = (0..names.len()).filter(|&i| is_scene(&names[i])).collect();
    match scenes.as_slice() {
        [one] => Ok(*one),
        [] => Err(format!("none of the dropped files ({}) is a .gltf or .glb", names.join(", "))),
        _ => Err(format!(
            "{} glTF files were dropped ({}); drop one with its files",
            scenes.len(),
            scenes.iter().map(|&i| names[i].as_str()).collect::<Vec<_>>().join(", ")
        )),
    }
}

fn is_scene(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower.ends_with(".gltf") || lower.ends_with(".glb")
}

/// For each path the document wants (`chiaro_scene::referenced_files`), the dropped file
/// of that name, if any; the loader names what is missing.
pub fn match_wanted(wanted: &[PathBuf], names: &[String]) -> Vec<(PathBuf, usize)> {
    wanted
        .iter()
        .filter_map(|path| {
            let name = path.file_name().and_then(|n| n.to_str())?;
            names.iter().position(|n| n == name).map(|i| (path.clone(), i))
        })
        .collect()
}

/// The path the page gives a dropped scene: a folder of its own, so that its relative
/// URIs resolve beside it.
pub fn dropped_path(name: &str) -> PathBuf {
    Path::new("dropped").join(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn the_one_gltf_is_the_scene_and_others_are_errors() {
        assert_eq!(scene_file(&names(&["a.bin", "Lamp.GLTF", "t.png"])).unwrap(), 1);
        assert!(scene_file(&names(&["a.bin"])).unwrap_err().starts_with("none of the dropped files (a.bin)"));
        assert!(scene_file(&names(&["a.glb", "b.gltf"])).unwrap_err().starts_with("2 glTF files were dropped"));
    }

    #[test]
    fn wanted_files_match_by_name_whatever_their_folder() {
        let wanted = vec![PathBuf::from("dropped/a.bin"), PathBuf::from("dropped/textures/t.png")];
        let got = match_wanted(&wanted, &names(&["t.png", "x.gltf", "a.bin"]));
        assert_eq!(got, vec![(wanted[0].clone(), 2), (wanted[1].clone(), 0)]);
        assert!(match_wanted(&wanted, &names(&["other.png"])).is_empty());
    }
}
