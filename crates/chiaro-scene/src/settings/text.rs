//! Where keys sit in a settings file's text, so that messages can say `render.width (line
//! 2)`: the dotted key set on a line (its table header above it and the key before its
//! `=`), and the line a dotted key is set on. A light reading of TOML's shape, enough for
//! the flat tables settings use; it never fails, it only finds less.

/// One `key = value` line: its 1-based number, the byte range it covers, the dotted key.
struct KeyLine {
    number: usize,
    start: usize,
    key: String,
}

/// The key part of a `key = value` line, dots kept, quotes and spaces dropped.
fn line_key(line: &str) -> Option<String> {
    let trimmed = line.trim_start();
    if trimmed.starts_with('#') || trimmed.starts_with('[') {
        return None;
    }
    let (key, _) = trimmed.split_once('=')?;
    let parts: Vec<String> = key.split('.').map(|p| p.trim().trim_matches(['"', '\'']).to_owned()).collect();
    (!parts.iter().any(String::is_empty)).then(|| parts.join("."))
}

/// The table a header line opens: `[shadows.directional]` gives `shadows.directional`.
fn header(line: &str) -> Option<String> {
    let trimmed = line.trim();
    let inner = trimmed
        .strip_prefix("[[")
        .and_then(|t| t.split("]]").next())
        .or_else(|| trimmed.strip_prefix('[').and_then(|t| t.split(']').next()))?;
    let parts: Vec<&str> = inner.split('.').map(|p| p.trim().trim_matches(['"', '\''])).collect();
    Some(parts.join("."))
}

fn key_lines(text: &str) -> (Vec<KeyLine>, Vec<(usize, usize, String)>) {
    let mut keys = Vec::new();
    let mut tables = Vec::new();
    let mut table = String::new();
    let mut start = 0;
    for (i, line) in text.split_inclusive('\n').enumerate() {
        if let Some(name) = header(line) {
            table = name;
            tables.push((i + 1, start, table.clone()));
        } else if let Some(key) = line_key(line) {
            let key = if table.is_empty() { key } else { format!("{table}.{key}") };
            keys.push(KeyLine { number: i + 1, start, key });
        }
        start += line.len();
    }
    (keys, tables)
}

/// The dotted key being set at byte `offset` (the nearest `key =` line at or above it, so
/// that a value spanning lines still finds its key; or the table header, for an error in
/// a header) and the 1-based line of `offset`.
pub(crate) fn key_at(text: &str, offset: usize) -> (Option<String>, usize) {
    let offset = offset.min(text.len());
    let line = text[..offset].matches('\n').count() + 1;
    let (keys, tables) = key_lines(text);
    let key = keys.iter().rev().find(|k| k.start <= offset).map(|k| (k.start, k.key.clone()));
    let table = tables.iter().rev().find(|t| t.1 <= offset).map(|t| (t.1, t.2.clone()));
    let found = match (key, table) {
        (Some(k), Some(t)) => Some(if t.0 > k.0 { t.1 } else { k.1 }),
        (k, t) => k.or(t).map(|(_, name)| name),
    };
    (found, line)
}

/// The 1-based line where `dotted` is set, if the text sets it.
pub(crate) fn line_of_key(text: &str, dotted: &str) -> Option<usize> {
    key_lines(text).0.into_iter().find(|k| k.key == dotted).map(|k| k.number)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "# comment\nwidth_top = 1\n[render]\nwidth = \"64\"\n\n[shadows.directional]\ncascade_ratios = [\n  0.1,\n  0.2,\n]\nfilter = 3\n";

    #[test]
    fn keys_are_found_with_their_tables_and_lines() {
        let at = |needle: &str| key_at(TEXT, TEXT.find(needle).unwrap());
        assert_eq!(at("\"64\""), (Some("render.width".into()), 4));
        assert_eq!(at("0.2"), (Some("shadows.directional.cascade_ratios".into()), 9));
        assert_eq!(at("3\n"), (Some("shadows.directional.filter".into()), 11));
        assert_eq!(at("= 1"), (Some("width_top".into()), 2));
        assert_eq!(at("directional]"), (Some("shadows.directional".into()), 6));
        assert_eq!(line_of_key(TEXT, "shadows.directional.filter"), Some(11));
        assert_eq!(line_of_key(TEXT, "render.height"), None);
    }
}
