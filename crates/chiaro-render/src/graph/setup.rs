//! What a pass declares for a frame, in its `setup`: the targets it creates (transient,
//! made for this frame and reused by the next) or keeps (persistent, such as the shadow
//! atlases), the targets it reads, overwrites or modifies, the ones it hands to the caller
//! (exports), and whether it has effects beyond its targets. A pass that declares no write
//! and no side effect does not run this frame.

use super::target::{Target, TargetDesc};
use crate::plan::FramePlan;

/// How a pass uses a target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// Samples it or tests against it, leaving it as it was.
    Read,
    /// Replaces every texel (a cleared attachment): what was there before does not matter.
    Write,
    /// Loads and adds to it: depends on what the earlier passes wrote.
    Modify,
}

/// Whether a target lives for one frame or across frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lifetime {
    /// Written afresh by each frame that uses it (its texture is reused).
    Transient,
    /// Keeps its contents from frame to frame; readable before anything writes it.
    Persistent,
}

/// A pass's declarations for one frame.
#[derive(Clone, Debug)]
pub struct PassSetup {
    /// The pass's name (`PassType::NAME`).
    pub name: &'static str,
    /// Targets the pass makes: their description and whether they outlive the frame.
    pub creates: Vec<(Target, TargetDesc, Lifetime)>,
    /// How the pass uses each target, in declaration order.
    pub accesses: Vec<(Target, Access)>,
    /// Targets handed back to the caller with the frame.
    pub exports: Vec<Target>,
    /// Whether the pass has effects beyond its targets (never culled).
    pub side_effect: bool,
    /// The device's depth-stencil format, for the scene depth targets.
    pub depth_format: wgpu::TextureFormat,
}

impl PassSetup {
    /// An empty declaration: the pass uses nothing, so it does not run.
    pub fn new(name: &'static str, depth_format: wgpu::TextureFormat) -> PassSetup {
        PassSetup {
            name,
            creates: Vec::new(),
            accesses: Vec::new(),
            exports: Vec::new(),
            side_effect: false,
            depth_format,
        }
    }

    /// Makes a transient target for this frame and writes all of it.
    pub fn create(&mut self, target: Target, desc: TargetDesc) -> &mut PassSetup {
        self.creates.push((target, desc, Lifetime::Transient));
        self.write(target)
    }

    /// Declares a target that persists across frames (it is made, or kept, whether or not
    /// this pass runs).
    pub fn persistent(&mut self, target: Target, desc: TargetDesc) -> &mut PassSetup {
        self.creates.push((target, desc, Lifetime::Persistent));
        self
    }

    /// The pass samples or tests against `target`, leaving it as it was.
    pub fn read(&mut self, target: Target) -> &mut PassSetup {
        self.accesses.push((target, Access::Read));
        self
    }

    /// The pass replaces every texel of `target`.
    pub fn write(&mut self, target: Target) -> &mut PassSetup {
        self.accesses.push((target, Access::Write));
        self
    }

    /// The pass loads `target` and adds to it.
    pub fn modify(&mut self, target: Target) -> &mut PassSetup {
        self.accesses.push((target, Access::Modify));
        self
    }

    /// The caller asked for this target: it keeps the pass that writes it, and is read
    /// back with the frame.
    pub fn export(&mut self, target: Target) -> &mut PassSetup {
        self.exports.push(target);
        self
    }

    /// The pass does something besides writing this frame's targets (such as drawing
    /// tiles into a persistent atlas that later frames trust), so it is never culled.
    pub fn side_effect(&mut self) -> &mut PassSetup {
        self.side_effect = true;
        self
    }

    /// Whether the pass has anything to do this frame.
    pub fn runs(&self) -> bool {
        self.side_effect || self.accesses.iter().any(|&(_, access)| access != Access::Read)
    }
}

/// A pass as the graph sees it before any device exists: its name and its setup.
#[derive(Clone, Copy)]
pub struct PassDeclaration {
    /// The pass's name.
    pub name: &'static str,
    /// Declares the pass's targets and accesses for a plan (`PassType::setup`).
    pub setup: fn(&FramePlan, &mut PassSetup),
}

impl PassDeclaration {
    /// Runs the pass's setup for `plan` on a device whose depth format is `depth_format`.
    pub fn declare(&self, plan: &FramePlan, depth_format: wgpu::TextureFormat) -> PassSetup {
        let mut setup = PassSetup::new(self.name, depth_format);
        (self.setup)(plan, &mut setup);
        setup
    }
}
