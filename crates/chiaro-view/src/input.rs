//! Window input as actions: winit's events (after egui has seen them) become camera
//! moves, picks, key commands, opened files and panel redraws. The pointer and the keys
//! held are this module's own state; the window's size is followed on the device here,
//! as it is no part of what the viewer shows.

use crate::action::Action;
use crate::camera::{FlyInput, Navigation};
use crate::gpu::window_size;
use crate::state::ViewerState;
use crate::viewer::Viewer;
use glam::Vec3;
use std::collections::HashSet;
use std::path::PathBuf;
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::keyboard::{Key, KeyCode, NamedKey, PhysicalKey};

/// Where a press turns into a click rather than a drag, in pixels.
const CLICK_SLOP_PX: f64 = 4.0;

/// The pointer and the keys, between events.
#[derive(Default)]
pub struct InputState {
    dragging: bool,
    /// Where the left button went down in the view: released near it, it is a click.
    pressed_at: Option<(f64, f64)>,
    /// Last cursor position, physical pixels.
    cursor: Option<(f64, f64)>,
    /// Keys held down (fly movement).
    keys: HashSet<KeyCode>,
}

impl InputState {
    /// The fly move the keys held ask for, over `seconds`, when flying.
    pub fn fly(&self, navigation: Navigation, seconds: f32) -> Option<Action> {
        if navigation != Navigation::Fly || self.keys.is_empty() {
            return None;
        }
        let held = |k: KeyCode| if self.keys.contains(&k) { 1.0 } else { 0.0 };
        let input: FlyInput = Vec3::new(
            held(KeyCode::KeyD) - held(KeyCode::KeyA),
            held(KeyCode::KeyE) - held(KeyCode::KeyQ),
            held(KeyCode::KeyS) - held(KeyCode::KeyW),
        );
        let fast = self.keys.contains(&KeyCode::ShiftLeft) || self.keys.contains(&KeyCode::ShiftRight);
        Some(Action::Fly { input, fast, seconds })
    }
}

/// The action a key press asks for, if any.
pub fn key_action(key: &Key, state: &ViewerState) -> Option<Action> {
    Some(match key.as_ref() {
        Key::Character("r") => Action::ResetView,
        Key::Character("c") if !state.scene.scene.cameras.is_empty() => Action::NextCamera,
        Key::Character("f") => Action::FrameSelected,
        Key::Character("v") => Action::SetNavigation(match state.camera.navigation {
            Navigation::Orbit => Navigation::Fly,
            Navigation::Fly => Navigation::Orbit,
        }),
        Key::Character("p") => Action::Screenshot { path: PathBuf::from("chiaro-view.png"), fatal: false },
        Key::Named(NamedKey::Escape) => Action::Quit { report: false },
        _ => return None,
    })
}

impl Viewer {
    /// Whether the pointer at `at` is over the panel (or there is no window).
    fn over_ui(&self, at: (f64, f64)) -> bool {
        self.gpu.as_ref().is_none_or(|gpu| gpu.over_ui(at, self.state.camera.view_size()))
    }

    fn cursor_over_ui(&self) -> bool {
        self.input.cursor.is_none_or(|c| self.over_ui(c))
    }

    /// The actions a window event (other than a redraw) asks for.
    pub(crate) fn window_input(&mut self, event: WindowEvent) -> Vec<Action> {
        let Some(gpu) = self.gpu.as_mut() else { return Vec::new() };
        let response = gpu.egui_state.on_window_event(&gpu.window, &event);
        let wants_keyboard = gpu.egui_ctx.egui_wants_keyboard_input();
        let refresh = |yes: bool| if yes { vec![Action::RefreshPanel] } else { Vec::new() };
        match event {
            WindowEvent::CloseRequested => vec![Action::Quit { report: false }],
            WindowEvent::Resized(size) => {
                gpu.resize(size.width, size.height);
                vec![Action::RefreshPanel]
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                let mut actions = Vec::new();
                if let (true, Some((x, y))) = (self.input.dragging, self.input.cursor) {
                    actions.push(Action::Drag { dx: (now.0 - x) as f32, dy: (now.1 - y) as f32 });
                }
                if response.repaint && (self.cursor_over_ui() || self.over_ui(now)) {
                    actions.push(Action::RefreshPanel);
                }
                self.input.cursor = Some(now);
                actions
            }
            WindowEvent::MouseInput { state, button: MouseButton::Left, .. } => {
                let on_ui = self.cursor_over_ui();
                self.input.dragging = state == ElementState::Pressed && !on_ui;
                // Over the view too while a panel field has the keyboard: egui sees the
                // click and lets go of it, so that keys move the camera again.
                let mut actions = refresh(on_ui || wants_keyboard);
                match state {
                    ElementState::Pressed => self.input.pressed_at = self.input.cursor.filter(|_| !on_ui),
                    ElementState::Released => actions.extend(self.click()),
                }
                actions
            }
            WindowEvent::MouseWheel { delta, .. } => {
                if self.cursor_over_ui() {
                    return vec![Action::RefreshPanel];
                }
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                vec![Action::Zoom(steps)]
            }
            WindowEvent::KeyboardInput { event, .. } => self.key_input(&event, wants_keyboard),
            WindowEvent::Focused(false) => {
                self.input.keys.clear();
                self.input.dragging = false;
                Vec::new()
            }
            WindowEvent::ScaleFactorChanged { scale_factor, .. } => {
                let (w, h) = self.state.camera.view_size();
                let _ = gpu.window.request_inner_size(window_size(w, h, scale_factor));
                vec![Action::RefreshPanel]
            }
            WindowEvent::DroppedFile(path) => vec![dropped_file(path, &self.state.settings.current)],
            _ => refresh(response.repaint),
        }
    }

    /// A release near where the button went down in the view picks what is there.
    fn click(&mut self) -> Option<Action> {
        let (Some((px, py)), Some((x, y))) = (self.input.pressed_at.take(), self.input.cursor) else { return None };
        if (x - px).hypot(y - py) >= CLICK_SLOP_PX {
            return None;
        }
        let [ox, oy] = self.gpu.as_ref()?.view_origin.map(f64::from);
        Some(Action::Pick { x: (x - ox) as f32, y: (y - oy) as f32 })
    }

    fn key_input(&mut self, event: &KeyEvent, wants_keyboard: bool) -> Vec<Action> {
        // A release always counts, or a key held into a text field flies on.
        if let PhysicalKey::Code(code) = event.physical_key
            && event.state == ElementState::Released
        {
            self.input.keys.remove(&code);
        }
        if wants_keyboard {
            return vec![Action::RefreshPanel];
        }
        if let PhysicalKey::Code(code) = event.physical_key
            && event.state == ElementState::Pressed
        {
            self.input.keys.insert(code);
        }
        if event.state == ElementState::Pressed && !event.repeat {
            return key_action(&event.logical_key, &self.state).into_iter().collect();
        }
        Vec::new()
    }
}

/// A dropped environment image (.hdr or .exr) lights the scene; any other file is opened
/// as a scene.
pub fn dropped_file(path: std::path::PathBuf, settings: &chiaro_scene::Settings) -> Action {
    use chiaro_scene::settings::EnvironmentSource;
    match EnvironmentSource::parse(&path.to_string_lossy()) {
        Ok(source @ EnvironmentSource::File(_)) => {
            let mut edited = settings.clone();
            edited.environment.source = source;
            Action::SetSettings(Box::new(edited))
        }
        _ => Action::Open(path),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state() -> ViewerState {
        let scene = chiaro_scene::demo::demo_scene(0);
        let view = chiaro_render::View::from_camera(&scene, 0, 64, 64);
        ViewerState::new(crate::ViewerConfig::new(scene, Default::default(), view))
    }

    #[test]
    fn keys_ask_for_what_the_help_says() {
        let state = state();
        let key = |c: &str| key_action(&Key::Character(c.into()), &state);
        assert!(matches!(key("r"), Some(Action::ResetView)));
        assert!(matches!(key("f"), Some(Action::FrameSelected)));
        assert!(matches!(key("v"), Some(Action::SetNavigation(Navigation::Fly))));
        assert!(matches!(key("p"), Some(Action::Screenshot { fatal: false, .. })));
        assert!(matches!(key_action(&Key::Named(NamedKey::Escape), &state), Some(Action::Quit { report: false })));
        assert!(key("x").is_none());
    }

    #[test]
    fn held_keys_fly_only_when_flying() {
        let mut input = InputState::default();
        input.keys.insert(KeyCode::KeyW);
        assert!(input.fly(Navigation::Orbit, 0.1).is_none());
        let Some(Action::Fly { input: direction, fast, .. }) = input.fly(Navigation::Fly, 0.1) else { panic!() };
        assert_eq!((direction, fast), (Vec3::new(0.0, 0.0, -1.0), false));
    }
}
