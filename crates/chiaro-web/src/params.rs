//! The page's URL parameters (`?scene=URL&width=W&height=H&camera=N&frames=N&panel=0`),
//! parsed and checked. Every default is `chiaro render`'s, so that a page and a native
//! render of the same file, camera and size can be compared.

use percent_encoding::percent_decode_str;

/// What the page was asked to show.
#[derive(Clone, Debug, PartialEq)]
pub struct PageParams {
    /// The scene's URL relative to the page; `None`: the built-in demo.
    pub scene: Option<String>,
    /// The canvas size in pixels; `None`: the settings' `render.width` / `render.height`.
    pub width: Option<u32>,
    pub height: Option<u32>,
    /// Camera by name or index (as `chiaro render --camera`); `None`: the scene's first,
    /// or one that frames it.
    pub camera: Option<String>,
    /// Render this many frames, report their times and stop; `None`: interactive.
    pub frames: Option<u32>,
    /// Frames rendered before the timed ones and not counted (shader compilation, caches).
    pub warmup: u32,
    /// Whether the settings panel is shown.
    pub panel: bool,
    /// A settings TOML file's URL (docs/settings.md), as `chiaro render --settings`.
    pub settings: Option<String>,
    /// `check=shaders`: compile every shader of the renderer with the browser's compiler,
    /// publish its errors and stop, rendering nothing.
    pub check_shaders: bool,
}

impl Default for PageParams {
    fn default() -> Self {
        PageParams {
            scene: None,
            width: None,
            height: None,
            camera: None,
            frames: None,
            warmup: 0,
            panel: true,
            settings: None,
            check_shaders: false,
        }
    }
}

/// Largest canvas side the page takes: WebGPU's guaranteed 2D texture size.
pub const MAX_SIDE: u32 = 8192;
/// Most frames a timed run renders.
pub const MAX_FRAMES: u32 = 100_000;

impl PageParams {
    /// Parses `location.search` (with or without its `?`); errors name the parameter.
    pub fn parse(search: &str) -> Result<PageParams, String> {
        let mut params = PageParams::default();
        for pair in search.trim_start_matches('?').split('&').filter(|p| !p.is_empty()) {
            let (key, raw) = pair.split_once('=').unwrap_or((pair, ""));
            let value = decode(raw).map_err(|e| format!("{key}: {e}"))?;
            match key {
                "scene" => params.scene = non_empty(value),
                "settings" => params.settings = non_empty(value),
                "camera" => params.camera = non_empty(value),
                "width" => params.width = Some(number(key, &value, 1, MAX_SIDE)?),
                "height" => params.height = Some(number(key, &value, 1, MAX_SIDE)?),
                "frames" => params.frames = Some(number(key, &value, 1, MAX_FRAMES)?),
                "warmup" => params.warmup = number(key, &value, 0, MAX_FRAMES)?,
                "panel" => {
                    params.panel = match value.as_str() {
                        "0" | "false" => false,
                        "1" | "true" => true,
                        _ => return Err(format!("panel={value}: expected 0 or 1")),
                    }
                }
                "check" => match value.as_str() {
                    "shaders" => params.check_shaders = true,
                    _ => return Err(format!("check={value}: expected shaders")),
                },
                // Other parameters (a cache-buster, say) are the page's host's business.
                _ => {}
            }
        }
        Ok(params)
    }
}

/// Query values encode spaces as `+` as well as `%20`.
fn decode(raw: &str) -> Result<String, String> {
    let spaced = raw.replace('+', " ");
    percent_decode_str(&spaced).decode_utf8().map(|s| s.into_owned()).map_err(|_| "is not UTF-8".to_string())
}

fn non_empty(value: String) -> Option<String> {
    (!value.is_empty()).then_some(value)
}

fn number(key: &str, value: &str, min: u32, max: u32) -> Result<u32, String> {
    match value.parse::<u32>() {
        Ok(n) if (min..=max).contains(&n) => Ok(n),
        _ => Err(format!("{key}={value}: expected a whole number from {min} to {max}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_parameter_is_read_and_defaults_are_the_cli_s() {
        let p =
            PageParams::parse("?scene=scenes/a%20b.gltf&width=64&height=48&camera=Main+cam&frames=3&warmup=2&panel=0")
                .unwrap();
        assert_eq!(p.scene.as_deref(), Some("scenes/a b.gltf"));
        assert_eq!((p.width, p.height, p.frames, p.warmup), (Some(64), Some(48), Some(3), 2));
        assert_eq!(p.camera.as_deref(), Some("Main cam"));
        assert!(!p.panel);
        assert!(PageParams::parse("check=shaders").unwrap().check_shaders);
        assert_eq!(PageParams::parse("").unwrap(), PageParams::default());
        assert_eq!(PageParams::parse("?x=1&scene=").unwrap(), PageParams::default());
    }

    #[test]
    fn bad_values_are_errors_naming_the_parameter() {
        for (query, start) in [
            ("width=0", "width=0: expected"),
            ("height=9000", "height=9000: expected"),
            ("frames=abc", "frames=abc: expected"),
            ("panel=maybe", "panel=maybe: expected 0 or 1"),
            ("scene=%FF", "scene: is not UTF-8"),
            ("check=all", "check=all: expected shaders"),
        ] {
            let error = PageParams::parse(query).unwrap_err();
            assert!(error.starts_with(start), "{query}: {error}");
        }
    }
}
