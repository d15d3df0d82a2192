//! Fits the LTC table to Chiaro's GGX lobe and writes it where `chiaro_math::ltc::table`
//! reads it: `cargo run --release -p chiaro-math --example fit_ltc`.

use chiaro_math::ltc::{encode_table, fit_table};
use std::path::Path;

fn main() -> std::io::Result<()> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let started = std::time::Instant::now();
    let table = fit_table(threads);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/ltc_ggx.bin");
    std::fs::write(&path, encode_table(&table))?;
    println!("fitted {} cells in {:.1} s into {}", table.len(), started.elapsed().as_secs_f32(), path.display());
    Ok(())
}
