//! docs/settings.md against the code: every key the code reads is documented and every
//! documented key exists, each range the documentation states is the `Bound` validation
//! checks (and each `Bound` is stated), and the documented values are the defaults.

use super::*;
use std::collections::{BTreeMap, BTreeSet};

/// A documented key: the comment beside it (with its continuation lines) and the line of
/// its example value.
struct DocumentedKey {
    comment: String,
    assignment: String,
}

fn settings_doc() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/settings.md");
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The documentation's example file: the first TOML code block.
fn example_toml(doc: &str) -> &str {
    let start = doc.find("```toml\n").expect("docs/settings.md has a TOML block") + "```toml\n".len();
    let len = doc[start..].find("```").expect("the TOML block ends");
    &doc[start..start + len]
}

/// `name = value` with a bare key before the `=`: a setting (written out or commented out).
fn assignment_key(text: &str) -> Option<&str> {
    let (key, _) = text.split_once('=')?;
    let key = key.trim();
    (!key.is_empty() && key.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')).then_some(key)
}

/// Every key of the example, dotted, with its comment. A comment line that sets no key
/// continues the comment of the key above it.
fn documented_keys(toml: &str) -> BTreeMap<String, DocumentedKey> {
    let mut keys = BTreeMap::new();
    let (mut table, mut last) = (String::new(), None::<String>);
    for line in toml.lines() {
        let trimmed = line.trim();
        if let Some(header) = trimmed.strip_prefix('[') {
            table = header.split(']').next().unwrap().to_owned();
            last = None;
            continue;
        }
        let commented = trimmed.strip_prefix('#').map(str::trim_start);
        let setting = commented.unwrap_or(trimmed);
        if let Some(key) = assignment_key(setting.split('#').next().unwrap()) {
            let (assignment, comment) = setting.split_once('#').unwrap_or((setting, ""));
            let dotted = format!("{table}.{key}");
            keys.insert(
                dotted.clone(),
                DocumentedKey { comment: comment.to_owned(), assignment: assignment.trim().to_owned() },
            );
            last = Some(dotted);
        } else if let (Some(more), Some(key)) = (commented, &last) {
            let entry = keys.get_mut(key).unwrap();
            entry.comment = format!("{} {more}", entry.comment);
        }
    }
    keys
}

/// The `A to B` intervals a comment states, such as "(1 to 16384)" or "from 256 to 8192".
fn stated_ranges(comment: &str) -> Vec<(f32, f32)> {
    let words: Vec<&str> = comment.split(|c: char| c.is_whitespace() || "(),;:".contains(c)).collect();
    words.windows(3).filter(|w| w[1] == "to").filter_map(|w| Some((w[0].parse().ok()?, w[2].parse().ok()?))).collect()
}

/// The dotted keys of a TOML table's values, tables descended into.
fn leaf_keys(table: &toml::Table, prefix: &str, out: &mut BTreeSet<String>) {
    for (key, value) in table {
        let dotted = if prefix.is_empty() { key.clone() } else { format!("{prefix}.{key}") };
        match value {
            toml::Value::Table(inner) => leaf_keys(inner, &dotted, out),
            _ => {
                out.insert(dotted);
            }
        }
    }
}

#[test]
fn every_key_in_code_is_documented_and_every_documented_key_exists() {
    let mut all = Settings::default();
    // The optional keys, so that they serialise too.
    all.lights.max_other_lights = Some(1);
    all.shadows.directional.cascade_ratios = Some(DEFAULT_CASCADE_RATIOS.to_vec());
    all.bake.samples = Some(1);
    all.bake.probe_samples = Some(1);
    all.scene.variant = Some("midnight".into());
    let mut in_code = BTreeSet::new();
    leaf_keys(&toml::Table::try_from(&all).unwrap(), "", &mut in_code);
    let doc = settings_doc();
    let documented: BTreeSet<String> = documented_keys(example_toml(&doc)).into_keys().collect();
    assert_eq!(documented, in_code, "keys in docs/settings.md against the keys Settings reads");
}

#[test]
fn documented_ranges_are_the_ones_validation_checks() {
    let doc = settings_doc();
    let documented = documented_keys(example_toml(&doc));
    let mut in_code: BTreeMap<&str, Vec<(f32, f32)>> = BTreeMap::new();
    for bound in bounds() {
        in_code.entry(bound.key).or_default().push((bound.min, bound.max));
        assert!(documented.contains_key(bound.key), "{} has a range but no documentation", bound.key);
    }
    for (key, entry) in &documented {
        let mut stated = stated_ranges(&entry.comment);
        let mut checked = in_code.get(key.as_str()).cloned().unwrap_or_default();
        stated.sort_by(|a, b| a.partial_cmp(b).unwrap());
        checked.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(stated, checked, "{key}: ranges in docs/settings.md ({:?}) against validation", entry.comment);
    }
    let msaa = &documented["render.msaa"].comment;
    assert!(msaa.contains(&render::msaa_choices_text()), "render.msaa's choices: {msaa}");
}

#[test]
fn documented_values_are_the_defaults() {
    let doc = settings_doc();
    let toml = example_toml(&doc);
    let mut read = Settings::parse(toml).unwrap();
    // The example spells out the default ratios, which unset means.
    let ratios = read.shadows.directional.cascade_ratios.take();
    assert_eq!(ratios.as_deref(), Some(&DEFAULT_CASCADE_RATIOS[..]));
    assert_eq!(read, Settings::default());
    // The commented-out keys document a value inside their range; the sample counts the
    // one the default quality picks.
    let documented = documented_keys(toml);
    let value_of = |key: &str| -> f32 {
        let example = &documented[key].assignment;
        example.split('=').nth(1).unwrap().trim().parse().unwrap()
    };
    assert!(lights::MAX_LOCAL_LIGHTS_CULLED.contains(value_of("lights.max_other_lights")));
    assert_eq!(value_of("bake.samples"), Settings::default().bake.texel_samples() as f32);
    assert_eq!(value_of("bake.probe_samples"), Settings::default().bake.probe_samples() as f32);
}
