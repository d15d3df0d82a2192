//! The lightmap baker: lightmap UVs (charts packed into atlases), a CPU path tracer over
//! chiaro-trace's BVH for lightmap texels and light probes, and bake directories (written
//! atomically, read back and checked against their scene).
//!
//! A `Scene` and `Settings` flow in; `BakeResult` flows out, and `bake_dir` writes it.
//! The renderer never reads files: `apply_bake_dir` attaches a bake to a `Scene`.

pub mod bake;
pub mod bake_dir;
pub mod channels;
pub mod charts;
pub mod convergence;
pub mod denoise;
pub mod emitters;
pub mod layout;
pub mod pack;
pub mod raster;
pub mod rng;
pub mod surface;
pub mod tracer;

pub use bake::{BakeError, BakeResult, BakeStats, Progress, Silent, bake};
pub use bake_dir::{
    BakeDirError, FORMAT_VERSION, LoadedBake, Manifest, apply_bake_dir, default_bake_dir, read_bake_dir, scene_hash,
    write_bake_dir,
};
