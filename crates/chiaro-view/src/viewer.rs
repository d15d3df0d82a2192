//! The viewer as winit runs it: its state, the device once the window exists, and the
//! event loop's calls turned into frames (frame.rs) and actions (input.rs, apply.rs).

use crate::ViewerConfig;
use crate::action::Action;
use crate::frame::PanelSchedule;
use crate::gpu::Gpu;
use crate::input::InputState;
use crate::script::Script;
use crate::state::ViewerState;
use anyhow::{Context, Result};
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::WindowId;

pub struct Viewer {
    pub state: ViewerState,
    /// The window and everything on the device, once the window is open.
    pub gpu: Option<Gpu>,
    pub input: InputState,
    pub panel: PanelSchedule,
    pub script: Option<Script>,
    /// Actions to apply at the start of the next frame (the opening comparison).
    pub pending: Vec<Action>,
    /// What ends the viewer with an error.
    pub failure: Option<anyhow::Error>,
    /// The viewer is to close.
    pub quit: bool,
    pub last_frame: Option<Instant>,
}

impl Viewer {
    /// A viewer of `config`, with no window yet: tests drive it by actions alone.
    pub fn new(config: ViewerConfig) -> Viewer {
        let script = config.script.clone();
        let compare_at_start = config.compare_at_start;
        Viewer {
            state: ViewerState::new(config),
            gpu: None,
            input: InputState::default(),
            panel: PanelSchedule::default(),
            script,
            pending: if compare_at_start { vec![Action::Compare] } else { Vec::new() },
            failure: None,
            quit: false,
            last_frame: None,
        }
    }

    /// Applies `actions` in order, stopping at the first that ends the viewer with an error.
    pub fn apply_all(&mut self, actions: impl IntoIterator<Item = Action>) {
        for action in actions {
            if self.failure.is_some() {
                return;
            }
            self.apply(action);
        }
    }

    /// Leaves the event loop once the viewer is to close.
    fn exit_if_done(&self, event_loop: &ActiveEventLoop) {
        if self.quit {
            event_loop.exit();
        }
    }
}

/// Opens the window and runs the viewer until it closes.
pub fn run(config: ViewerConfig) -> Result<()> {
    let event_loop = EventLoop::new().context("cannot open a window (no display?)")?;
    let mut viewer = Viewer::new(config);
    event_loop.run_app(&mut viewer).context("the window's event loop failed")?;
    match viewer.failure {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gpu.is_some() {
            return;
        }
        match Gpu::open(event_loop, &self.state) {
            Ok(gpu) => {
                let (w, h) = self.state.camera.view_size();
                let adapter = &gpu.renderer.ctx.adapter_info.name;
                let title = self.state.scene.title();
                eprintln!("chiaro: viewing {} ({w}x{h}) on {adapter}", title.trim_start_matches("chiaro view: "));
                gpu.window.request_redraw();
                self.gpu = Some(gpu);
            }
            Err(e) => self.fail_with(e),
        }
        self.exit_if_done(event_loop);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        if let WindowEvent::RedrawRequested = event {
            if let Err(e) = self.redraw() {
                self.fail_with(e);
            } else if let Some(script) = &self.script {
                let actions = script.after_frame(&self.state.stats);
                self.apply_all(actions);
            }
        } else {
            let actions = self.window_input(event);
            self.apply_all(actions);
        }
        self.exit_if_done(event_loop);
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        // A real-time view: draw again as soon as the last frame is done.
        if let Some(gpu) = &self.gpu {
            gpu.window.request_redraw();
        }
    }
}
