//! Compiles a frame's pass declarations into what runs, on the CPU (no device): the
//! declarations of every pass flow in, in the order of the pass list; the passes that run
//! (in an order every read respects), the targets to make, the exports and the passes
//! culled flow out.
//!
//! As in Filament's FrameGraph, each write makes a new version of a target and a read sees
//! the latest version an earlier pass wrote, which makes the writer a dependency of the
//! reader. Starting from the sinks (the output, the exports) and the passes with side
//! effects, the graph keeps every pass some kept pass depends on and culls the rest: a
//! deferred G-buffer view keeps the G-buffer but drops the light volumes, and the tone
//! mapper drops out when a debug view writes the output after it.

use super::setup::{Access, Lifetime, PassDeclaration, PassSetup};
use super::target::{OUTPUT, Target, TargetDesc};
use crate::error::RenderError;
use crate::plan::FramePlan;
use std::collections::{BTreeMap, HashMap};
use std::fmt;

/// A frame's passes, ordered and culled, and its targets.
#[derive(Clone, Debug, Default)]
pub struct FrameGraph {
    /// Indices into the pass list of the passes that run, in the order they run.
    pub order: Vec<usize>,
    /// Their names, in the same order.
    pub passes: Vec<&'static str>,
    /// Passes that declared work this frame but whose outputs nobody reads.
    pub culled: Vec<&'static str>,
    /// Every target a running pass creates, and every persistent one, by name.
    pub targets: BTreeMap<Target, (TargetDesc, Lifetime)>,
    /// Targets the caller asked for, written by a running pass.
    pub exports: Vec<Target>,
}

impl FrameGraph {
    /// Declares every pass of `list` for `plan` (with the device's depth format) and
    /// compiles the result.
    pub fn compile(
        list: &[PassDeclaration],
        plan: &FramePlan,
        depth_format: wgpu::TextureFormat,
    ) -> Result<FrameGraph, RenderError> {
        let setups: Vec<PassSetup> = list.iter().map(|d| d.declare(plan, depth_format)).collect();
        compile_setups(&setups)
    }

    /// Whether `target` exists this frame: created by a running pass, or persistent.
    pub fn has(&self, target: Target) -> bool {
        self.targets.contains_key(&target)
    }
}

fn graph_error(message: String) -> RenderError {
    RenderError::FrameGraph(message)
}

/// Compiles declarations given in pass-list order.
pub fn compile_setups(setups: &[PassSetup]) -> Result<FrameGraph, RenderError> {
    let persistent = persistent_targets(setups)?;
    let running: Vec<usize> = (0..setups.len()).filter(|&i| setups[i].runs()).collect();
    // Per running pass, the passes whose versions it reads.
    let mut depends_on: HashMap<usize, Vec<usize>> = HashMap::new();
    let mut latest: HashMap<Target, usize> = HashMap::new();
    let mut created: HashMap<Target, usize> = HashMap::new();
    for &i in &running {
        let setup = &setups[i];
        for (target, _, lifetime) in &setup.creates {
            if *lifetime == Lifetime::Transient
                && let Some(other) = created.insert(*target, i)
            {
                return Err(graph_error(format!(
                    "the {} and {} passes both create {target}",
                    setups[other].name, setup.name
                )));
            }
        }
        let deps = depends_on.entry(i).or_default();
        for &(target, access) in &setup.accesses {
            if access != Access::Write {
                match latest.get(&target) {
                    Some(&writer) => deps.push(writer),
                    None if persistent.contains_key(&target) => {}
                    None => {
                        return Err(graph_error(format!(
                            "the {} pass reads {target}, which no earlier pass writes",
                            setup.name
                        )));
                    }
                }
            }
            if access != Access::Read {
                if target != OUTPUT && !created.contains_key(&target) && !persistent.contains_key(&target) {
                    return Err(graph_error(format!("the {} pass writes {target}, which no pass creates", setup.name)));
                }
                latest.insert(target, i);
            }
        }
    }
    let mut sinks = vec![OUTPUT];
    sinks.extend(running.iter().flat_map(|&i| setups[i].exports.iter().copied()));
    let mut kept = vec![false; setups.len()];
    for &i in &running {
        kept[i] = setups[i].side_effect;
    }
    for target in &sinks {
        if let Some(&writer) = latest.get(target) {
            kept[writer] = true;
        }
    }
    // Dependencies point to earlier passes, so one walk from the last pass keeps them all.
    for &i in running.iter().rev() {
        if kept[i] {
            for &dep in &depends_on[&i] {
                kept[dep] = true;
            }
        }
    }
    let order: Vec<usize> = running.iter().copied().filter(|&i| kept[i]).collect();
    let mut targets: BTreeMap<Target, (TargetDesc, Lifetime)> =
        persistent.into_iter().map(|(t, desc)| (t, (desc, Lifetime::Persistent))).collect();
    for &i in &order {
        for &(target, desc, lifetime) in &setups[i].creates {
            if lifetime == Lifetime::Transient {
                targets.insert(target, (desc, lifetime));
            }
        }
    }
    let mut exports: Vec<Target> = Vec::new();
    for &i in &order {
        for &t in &setups[i].exports {
            if !exports.contains(&t) {
                exports.push(t);
            }
        }
    }
    Ok(FrameGraph {
        passes: order.iter().map(|&i| setups[i].name).collect(),
        culled: running.iter().filter(|&&i| !kept[i]).map(|&i| setups[i].name).collect(),
        order,
        targets,
        exports,
    })
}

/// Every persistent target declared, whether or not its pass runs; one description each.
fn persistent_targets(setups: &[PassSetup]) -> Result<HashMap<Target, TargetDesc>, RenderError> {
    let mut persistent = HashMap::new();
    for setup in setups {
        for &(target, desc, lifetime) in &setup.creates {
            if lifetime == Lifetime::Persistent
                && let Some(other) = persistent.insert(target, desc)
                && other != desc
            {
                return Err(graph_error(format!("{target} is declared persistent twice, differently")));
            }
        }
    }
    Ok(persistent)
}

impl fmt::Display for FrameGraph {
    /// The passes in order, what was culled, and the targets.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "frame graph: {}", self.passes.join(", "))?;
        if !self.culled.is_empty() {
            write!(f, " (culled: {})", self.culled.join(", "))?;
        }
        for (target, (desc, lifetime)) in &self.targets {
            write!(
                f,
                "\n  {target}: {:?} {:?}, {} sample(s), {} layer(s), {lifetime:?}",
                desc.format, desc.size, desc.samples, desc.layers
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::target::{ATTACHMENT_SAMPLED, TargetDesc};

    const HDR: Target = Target("hdr");
    const ATLAS: Target = Target("atlas");
    const GBUFFER: Target = Target("gbuffer");

    fn desc() -> TargetDesc {
        TargetDesc::view_sized(wgpu::TextureFormat::Rgba16Float, ATTACHMENT_SAMPLED)
    }

    fn setup(name: &'static str, f: impl FnOnce(&mut PassSetup)) -> PassSetup {
        let mut s = PassSetup::new(name, wgpu::TextureFormat::Depth32FloatStencil8);
        f(&mut s);
        s
    }

    #[test]
    fn a_pass_may_not_read_what_no_earlier_pass_wrote() {
        let tonemap = setup("tonemap", |s| {
            s.read(HDR).write(OUTPUT);
        });
        let forward = setup("forward", |s| {
            s.create(HDR, desc());
        });
        let graph = compile_setups(&[forward.clone(), tonemap.clone()]).unwrap();
        assert_eq!(graph.passes, ["forward", "tonemap"]);
        let e = compile_setups(&[tonemap, forward]).unwrap_err();
        assert!(e.to_string().contains("the tonemap pass reads hdr, which no earlier pass writes"), "{e}");
    }

    #[test]
    fn passes_whose_outputs_nobody_reads_are_culled() {
        let gbuffer = setup("gbuffer", |s| {
            s.create(GBUFFER, desc()).create(HDR, desc());
        });
        let lights = setup("lights", |s| {
            s.read(GBUFFER).modify(HDR);
        });
        let tonemap = setup("tonemap", |s| {
            s.read(HDR).write(OUTPUT);
        });
        let debug = setup("debug", |s| {
            s.read(GBUFFER).write(OUTPUT);
        });
        let graph = compile_setups(&[gbuffer.clone(), lights.clone(), tonemap.clone(), debug]).unwrap();
        // The debug view writes the output last: the tone mapper and the lights it read
        // are not needed.
        assert_eq!(graph.passes, ["gbuffer", "debug"]);
        assert_eq!(graph.culled, ["lights", "tonemap"]);
        let graph = compile_setups(&[gbuffer, lights, tonemap]).unwrap();
        assert_eq!(graph.passes, ["gbuffer", "lights", "tonemap"]);
    }

    #[test]
    fn side_effects_and_exports_keep_a_pass_and_persistent_targets_need_no_writer() {
        let shadows = setup("shadows", |s| {
            s.persistent(ATLAS, desc()).modify(ATLAS).side_effect();
        });
        let idle_shadows = setup("shadows", |s| {
            s.persistent(ATLAS, desc());
        });
        let aov = setup("aov", |s| {
            s.create(GBUFFER, desc()).export(GBUFFER);
        });
        let forward = setup("forward", |s| {
            s.read(ATLAS).create(HDR, desc());
        });
        let tonemap = setup("tonemap", |s| {
            s.read(HDR).write(OUTPUT);
        });
        let graph = compile_setups(&[shadows, aov.clone(), forward.clone(), tonemap.clone()]).unwrap();
        assert_eq!(graph.passes, ["shadows", "aov", "forward", "tonemap"]);
        assert_eq!(graph.exports, [GBUFFER]);
        // No tile to draw: the atlas is read as the last frame left it.
        let graph = compile_setups(&[idle_shadows, forward, tonemap]).unwrap();
        assert_eq!(graph.passes, ["forward", "tonemap"]);
        assert!(graph.has(ATLAS));
    }

    #[test]
    fn a_target_is_created_once_and_written_only_when_made() {
        let a = setup("a", |s| {
            s.create(HDR, desc());
        });
        let b = setup("b", |s| {
            s.create(HDR, desc());
        });
        let e = compile_setups(&[a, b]).unwrap_err();
        assert!(e.to_string().contains("the a and b passes both create hdr"), "{e}");
        let stray = setup("stray", |s| {
            s.write(GBUFFER);
        });
        let e = compile_setups(&[stray]).unwrap_err();
        assert!(e.to_string().contains("the stray pass writes gbuffer, which no pass creates"), "{e}");
    }
}
