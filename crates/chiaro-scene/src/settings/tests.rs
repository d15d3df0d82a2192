//! Parsing, defaults, validation and messages of the whole settings file.

use super::*;
use crate::environment::{EnvironmentMap, SceneEnvironment};
use crate::types::Scene;
use chiaro_math::shadow::ShadowFilter;
use glam::Vec3;

#[test]
fn empty_file_gives_defaults() {
    assert_eq!(Settings::parse("").unwrap(), Settings::default());
}

#[test]
fn fields_override_defaults() {
    let s = Settings::parse("[render]\nexposure_ev100 = 2.5\nambient = [0, 0, 0]\n").unwrap();
    assert_eq!(s.render.exposure_ev100, 2.5);
    assert_eq!(s.render.ambient, [0.0; 3]);
    assert_eq!(s.render.width, 1280);
}

#[test]
fn unknown_keys_are_named() {
    let e = Settings::parse("[render]\nexposure = 2\n").unwrap_err();
    assert!(e.contains("exposure"), "{e}");
    let e = Settings::parse("[shadowz]\n").unwrap_err();
    assert!(e.contains("shadowz"), "{e}");
}

#[test]
fn settings_written_as_toml_read_back_equal() {
    let mut s = Settings::default();
    assert_eq!(Settings::parse(&s.to_toml()).unwrap(), s);
    s.render.msaa = 1;
    s.render.path = RenderPath::Deferred;
    s.lights.culling = LightCulling::PerObject;
    s.lights.max_other_lights = Some(300);
    s.shadows.directional.cascade_count = 3;
    s.shadows.directional.cascade_ratios = Some(vec![0.2, 0.6]);
    s.shadows.directional.cascade_blend = CascadeBlend::Dither;
    s.shadows.other.filter = "tent5x5".into();
    s.lighting.mixed_mode = MixedMode::Shadowmask;
    s.render.light_buffer = LightBuffer::LdrExp2;
    let text = s.to_toml();
    assert_eq!(Settings::parse(&text).unwrap(), s, "{text}");
}

#[test]
fn out_of_range_values_are_named() {
    let e = Settings::parse("[lights]\nmax_other_lights = 4097\n").unwrap_err();
    assert!(e.starts_with("lights.max_other_lights"), "{e}");
    // The forward path without culling shades at most 64; culled lists up to 4096.
    let no_culling = "[render]\npath = \"forward\"\n[lights]\nculling = \"none\"\nmax_other_lights = 65\n";
    let e = Settings::parse(no_culling).unwrap_err();
    assert!(e.starts_with("lights.max_other_lights"), "{e}");
    let clustered = "[render]\npath = \"forward\"\n[lights]\nmax_other_lights = 4096\n";
    assert!(Settings::parse(clustered).is_ok(), "clustered forward shades up to 4096");
    assert!(Settings::parse("[lights]\nmax_other_lights = 65\n").is_ok(), "deferred shades up to 4096");
    for bad in ["[render]\nmsaa = 3\n", "[render]\nmsaa = 16\n", "[render]\nmsaa = 0\n"] {
        let e = Settings::parse(bad).unwrap_err();
        assert!(e.starts_with("render.msaa"), "{e}");
    }
    let e = Settings::parse("[lights]\nculling = \"tiled\"\n").unwrap_err();
    assert!(e.starts_with("lights.culling"), "{e}");
    let e = Settings::parse("[render]\ndeferred_antialiasing = \"smaa\"\n").unwrap_err();
    assert!(e.starts_with("render.deferred_antialiasing") && e.contains("`fxaa` or `none`"), "{e}");
    let none = Settings::parse("[render]\ndeferred_antialiasing = \"none\"\n").unwrap();
    assert_eq!(none.render.deferred_antialiasing, DeferredAntialiasing::None);
    let e = Settings::parse("[render]\nwidth = 0\n").unwrap_err();
    assert!(e.starts_with("render.width"), "{e}");
    let e = Settings::parse("[lights]\nrange_threshold_lux = 0.0\n").unwrap_err();
    assert!(e.starts_with("lights.range_threshold_lux"), "{e}");
    let e = Settings::parse("[render]\nambient = [0, -1, 0]\n").unwrap_err();
    assert!(e.starts_with("render.ambient"), "{e}");
}

#[test]
fn shadow_settings_parse_and_validate() {
    let s = Settings::parse(
        "[shadows]\nmax_distance = 40\n[shadows.directional]\nfilter = \"tent5x5\"\ncascade_count = 2\ncascade_blend = \"dither\"\n",
    )
    .unwrap();
    assert_eq!(s.shadows.max_distance, 40.0);
    assert_eq!(s.shadows.directional.shadow_filter(), ShadowFilter::Tent5x5);
    assert_eq!(s.shadows.directional.cascade_blend, CascadeBlend::Dither);
    assert_eq!(s.shadows.technique, crate::settings::ShadowTechnique::Atlas, "atlas stays the default");
    let v = Settings::parse("[shadows]\ntechnique = \"virtual\"\nvirtual_pool_mb = 64\n").unwrap();
    assert_eq!((v.shadows.technique, v.shadows.virtual_pool_mb), (crate::settings::ShadowTechnique::Virtual, 64));
    for (text, key) in [
        ("[shadows.directional]\natlas_size = 3000\n", "shadows.directional.atlas_size"),
        ("[shadows.directional]\nfilter = \"gauss\"\n", "shadows.directional.filter"),
        ("[shadows.directional]\ncascade_count = 5\n", "shadows.directional.cascade_count"),
        ("[shadows.directional]\ncascade_ratios = [0.5, 0.2, 0.7]\n", "shadows.directional.cascade_ratios"),
        ("[shadows.directional]\ncascade_ratios = [0.1, 0.2, 0.3, 0.4]\n", "shadows.directional.cascade_ratios"),
        ("[shadows.directional]\ncascade_count = 3\ncascade_ratios = [0.1]\n", "shadows.directional.cascade_ratios"),
        ("[shadows]\nmax_distance = -1\n", "shadows.max_distance"),
        ("[shadows]\ncontact_length = 0\n", "shadows.contact_length"),
        ("[shadows]\ncontact_steps = 65\n", "shadows.contact_steps"),
        ("[shadows]\ncontact_thickness = 11\n", "shadows.contact_thickness"),
        ("[shadows]\nvirtual_pool_mb = 8\n", "shadows.virtual_pool_mb"),
        ("[shadows.other]\natlas_size = 100\n", "shadows.other.atlas_size"),
        ("[shadows.other]\nfilter = \"box\"\n", "shadows.other.filter"),
    ] {
        let e = Settings::parse(text).unwrap_err();
        assert!(e.starts_with(key), "{e}");
    }
    let e = Settings::parse("[shadows.directional]\ncascade_blend = \"smooth\"\n").unwrap_err();
    assert!(e.contains("smooth"), "{e}");
    let e = Settings::parse("[shadows]\ntechnique = \"cascades\"\n").unwrap_err();
    assert!(e.contains("cascades"), "{e}");
}

#[test]
fn messages_name_the_key_and_its_line() {
    for (text, expected) in [
        ("[render]\nwidth = \"64\"\n", "render.width (line 2): invalid type: string \"64\", expected u32"),
        ("[render]\nwidth = 64\nwidth = 65\n", "render.width (line 3): duplicate key"),
        (
            "\n[shadows.directional]\nfilter = 3\n",
            "shadows.directional.filter (line 3): invalid type: integer `3`, expected a string",
        ),
        (
            "[shadows.directional]\ncascade_blend = \"smooth\"\n",
            "shadows.directional.cascade_blend (line 2): unknown variant `smooth`, expected one of `hard`, \
             `soft`, `dither`",
        ),
        ("[render]\n\nwidth = 0\n", "render.width (line 3): 0 is out of range (1 to 16384)"),
        (
            "[shadows.directional]\ncascade_ratios = [0.1, 0.2, 0.3, 0.4]\n",
            "shadows.directional.cascade_ratios (line 2): takes cascade_count - 1 = 3 entries (the last \
             cascade ends at max_distance), got 4",
        ),
        (
            "[lights]\nrange_threshold_lux = 1e-40\n",
            "lights.range_threshold_lux (line 2): 1e-40 is out of range (1e-6 to 1000000)",
        ),
    ] {
        let e = Settings::parse(text).unwrap_err();
        assert!(e.starts_with(expected), "{text:?}: {e}");
    }
}

#[test]
fn cascade_ratios_take_one_fewer_than_the_cascades() {
    let s = Settings::parse("[shadows.directional]\ncascade_count = 2\ncascade_ratios = [0.3]\n").unwrap();
    assert_eq!(s.shadows.directional.ratios()[0], 0.3);
    // Unset, the defaults serve any count.
    let s = Settings::parse("[shadows.directional]\ncascade_count = 2\n").unwrap();
    assert_eq!(s.shadows.directional.ratios(), DEFAULT_CASCADE_RATIOS);
}

#[test]
fn environment_sources_parse_and_bad_ones_name_the_key() {
    let s = Settings::parse("[environment]\nsource = \"sky\"\nintensity = 2.5\nrotation_deg = -90\n").unwrap();
    assert_eq!(s.environment.source, EnvironmentSource::Sky);
    assert_eq!((s.environment.intensity, s.environment.rotation_deg), (2.5, -90.0));
    assert!(s.environment.enabled_for(&Scene::default()) && s.environment.background);
    let s = Settings::parse("[environment]\nsource = \"maps/Studio.HDR\"\nmode = \"baked\"\n").unwrap();
    assert_eq!(s.environment.source, EnvironmentSource::File("maps/Studio.HDR".into()));
    assert_eq!(s.environment.mode, EnvironmentMode::Baked);
    assert!(!Settings::default().environment.enabled_for(&Scene::default()));
    // A file's own environment lights it under `none`; `ambient` keeps the constant term.
    let own = SceneEnvironment::new("EXT_lights_image_based light 0".into(), EnvironmentMap::uniform(Vec3::ONE));
    let carrying = Scene { environment: Some(own), ..Scene::default() };
    let default = Settings::default().environment;
    assert!(default.enabled_for(&carrying));
    assert_eq!(default.describe(&carrying), "EXT_lights_image_based light 0");
    let ambient = Settings::parse("[environment]\nsource = \"ambient\"\n").unwrap().environment;
    assert_eq!(ambient.source, EnvironmentSource::Ambient);
    assert!(!ambient.enabled_for(&carrying));
    assert_eq!(ambient.describe(&carrying), "ambient");
    for (text, expected) in [
        ("[environment]\nsource = \"studio.png\"\n", "environment.source (line 2): \"studio.png\" is not none"),
        ("[environment]\nintensity = -1\n", "environment.intensity (line 2): -1 is out of range (0 to 1000000)"),
        ("[environment]\nrotation_deg = 400\n", "environment.rotation_deg (line 2): 400 is out of range"),
        ("[environment]\nmode = \"live\"\n", "environment.mode (line 2): unknown variant `live`"),
    ] {
        let e = Settings::parse(text).unwrap_err();
        assert!(e.starts_with(expected), "{text:?}: {e}");
    }
}

#[test]
fn an_environment_image_is_found_beside_the_settings_file() {
    let dir = std::env::temp_dir().join(format!("chiaro-settings-env-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("settings.toml");
    std::fs::write(&file, "[environment]\nsource = \"sky.exr\"\n").unwrap();
    let s = Settings::load(&file).unwrap();
    assert_eq!(s.environment.source, EnvironmentSource::File(dir.join("sky.exr")));
    // Saved and read again, the path stays as it was resolved.
    assert_eq!(Settings::parse(&s.to_toml()).unwrap().environment, s.environment);
    std::fs::remove_dir_all(&dir).unwrap();
}
