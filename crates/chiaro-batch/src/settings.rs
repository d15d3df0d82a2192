//! A job's `settings`: a JSON object shaped like settings.toml (sections of keys) merged
//! over the batch's base settings, key by key, then parsed and validated as a settings
//! file is. The base's TOML text and the job's object flow in; the job's settings flow out,
//! or a message starting with `settings:` that names the key.

use chiaro_scene::Settings;
use serde_json::{Map, Value};

/// `overrides` merged over `base`: a section the job names keeps the base's other keys.
pub fn merged_settings(base: &Settings, overrides: &Map<String, Value>) -> Result<Settings, String> {
    if overrides.is_empty() {
        return Ok(base.clone());
    }
    let mut table: toml::Table = toml::from_str(&base.to_toml()).expect("settings write TOML they read back");
    let overrides = toml::Table::try_from(overrides).map_err(|e| format!("settings: cannot be read as TOML: {e}"))?;
    merge(&mut table, overrides);
    let text = toml::to_string(&table).map_err(|e| format!("settings: cannot be written as TOML: {e}"))?;
    Settings::parse(&text).map_err(|message| format!("settings: {}", without_line(&message)))
}

/// `over`'s keys set in `into`, tables merged key by key, anything else replaced.
fn merge(into: &mut toml::Table, over: toml::Table) {
    for (key, value) in over {
        match (into.get_mut(&key), value) {
            (Some(toml::Value::Table(existing)), toml::Value::Table(section)) => merge(existing, section),
            (_, value) => {
                into.insert(key, value);
            }
        }
    }
}

/// A settings message without the line of the merged text it cites (a line of a file the
/// user never saw): `render.msaa (line 7): ...` becomes `render.msaa: ...`.
fn without_line(message: &str) -> String {
    if let Some(rest) = message.strip_prefix("line ")
        && let Some((digits, rest)) = rest.split_once(": ")
        && digits.bytes().all(|b| b.is_ascii_digit())
    {
        return rest.to_string();
    }
    if let Some(start) = message.find(" (line ")
        && let Some(len) = message[start..].find("): ")
        && message[start + 7..start + len].bytes().all(|b| b.is_ascii_digit())
    {
        return format!("{}{}", &message[..start], &message[start + len + 1..]);
    }
    message.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn object(value: Value) -> Map<String, Value> {
        value.as_object().unwrap().clone()
    }

    #[test]
    fn a_job_section_keeps_the_base_keys_it_does_not_name() {
        let mut base = Settings::default();
        base.render.width = 320;
        base.render.exposure_ev100 = 11.0;
        let merged = merged_settings(&base, &object(json!({"render": {"msaa": 1}}))).unwrap();
        assert_eq!((merged.render.msaa, merged.render.width, merged.render.exposure_ev100), (1, 320, 11.0));
        assert_eq!(merged_settings(&base, &Map::new()).unwrap(), base);
    }

    #[test]
    fn bad_settings_name_the_key_without_the_merged_text_line() {
        let e = merged_settings(&Settings::default(), &object(json!({"render": {"mssa": 1}}))).unwrap_err();
        assert!(e.starts_with("settings: ") && e.contains("mssa") && !e.contains("(line"), "{e}");
        let e = merged_settings(&Settings::default(), &object(json!({"render": {"width": 0}}))).unwrap_err();
        assert!(e.starts_with("settings: render.width: ") && !e.contains("(line"), "{e}");
        let e = merged_settings(&Settings::default(), &object(json!({"rendr": {}}))).unwrap_err();
        assert!(e.contains("rendr"), "{e}");
        let e = merged_settings(&Settings::default(), &object(json!({"render": {"msaa": null}}))).unwrap_err();
        assert!(e.starts_with("settings: "), "{e}");
    }

    #[test]
    fn line_citations_are_dropped_and_nothing_else() {
        assert_eq!(without_line("render.msaa (line 7): 3 is not 1 or 4"), "render.msaa: 3 is not 1 or 4");
        assert_eq!(without_line("line 12: unknown field `x`"), "unknown field `x`");
        assert_eq!(without_line("render.width: 0 is below 1"), "render.width: 0 is below 1");
    }
}
