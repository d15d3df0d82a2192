//! A short, fixed-seed fuzzing pass for CI: no input may make the importer or the
//! settings parser panic, and the mutants must reach both outcomes (some accepted, some
//! refused), or the pass would prove nothing.

use chiaro_fuzz::{Target, fuzz};

fn check(target: Target, inputs: u64) {
    let report = fuzz(target, inputs, 2026, None).unwrap();
    assert_eq!(report.inputs, inputs);
    let crashes: Vec<String> = report
        .crashes
        .iter()
        .take(5)
        .map(|c| format!("{} on {:?}", c.message, String::from_utf8_lossy(&c.input[..c.input.len().min(300)])))
        .collect();
    assert!(report.crashes.is_empty(), "{} crashes, the first: {crashes:#?}", report.crashes.len());
    assert!(report.accepted > inputs / 50, "{target:?}: only {} of {inputs} accepted", report.accepted);
    assert!(report.refused > inputs / 10, "{target:?}: only {} of {inputs} refused", report.refused);
    println!("{target:?}: {report:?}");
}

#[test]
fn the_gltf_importer_survives_mutated_assets() {
    check(Target::Gltf, 1500);
}

#[test]
fn the_settings_parser_survives_mutated_settings() {
    check(Target::Settings, 50_000);
}
