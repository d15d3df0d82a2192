//! Lists of names in messages: a warning about 235 lights says how many there are and
//! names the first few, so that it stays one line a person reads.

/// How many names a message lists before it counts the rest.
pub const NAMES_SHOWN: usize = 4;

/// `names` joined by commas, the first `NAMES_SHOWN` of them, then how many more:
/// `'a', 'b', 'c', 'd' and 231 more`. Empty names read as `(unnamed)`.
pub fn few_names<S: AsRef<str>>(names: &[S]) -> String {
    let shown: Vec<String> = names
        .iter()
        .take(NAMES_SHOWN)
        .map(|n| match n.as_ref() {
            "" => "(unnamed)".to_string(),
            name => format!("'{name}'"),
        })
        .collect();
    let rest = names.len().saturating_sub(NAMES_SHOWN);
    if rest == 0 { shown.join(", ") } else { format!("{} and {rest} more", shown.join(", ")) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_list_names_the_first_few_and_counts_the_rest() {
        let many: Vec<String> = (0..235).map(|i| format!("lamp {i}")).collect();
        let line = few_names(&many);
        assert_eq!(line, "'lamp 0', 'lamp 1', 'lamp 2', 'lamp 3' and 231 more");
        assert_eq!(few_names(&["a", ""]), "'a', (unnamed)");
        assert_eq!(few_names(&["a", "b", "c", "d"]), "'a', 'b', 'c', 'd'");
        assert_eq!(few_names::<&str>(&[]), "");
    }
}
