//! The scripted run (`--exit-after-frames N`, with `--screenshot` and
//! `--screenshot-window`): after N frames, the same actions a user's P and Escape
//! would give, except that a failed screenshot ends the run with its error.

use crate::action::Action;
use crate::state::FrameStats;
use std::path::PathBuf;

/// Frames to show, and what to write after them, before the viewer exits.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Script {
    pub frames: u32,
    /// The 3D view, as `chiaro render` writes it (PNG or EXR).
    pub screenshot: Option<PathBuf>,
    /// The whole window as the screen shows it (PNG).
    pub screenshot_window: Option<PathBuf>,
}

impl Script {
    /// What to do once a frame is shown: nothing until the last frame, then write the
    /// screenshots, report the frame times and quit.
    pub fn after_frame(&self, stats: &FrameStats) -> Vec<Action> {
        if stats.frames < self.frames {
            return Vec::new();
        }
        let view = self.screenshot.clone().map(|path| Action::Screenshot { path, fatal: true });
        let window = self.screenshot_window.clone().map(Action::ScreenshotWindow);
        view.into_iter().chain(window).chain([Action::Quit { report: true }]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_run_writes_its_screenshots_and_quits_after_its_frames() {
        let script = Script { frames: 3, screenshot: Some("a.png".into()), screenshot_window: None };
        let mut stats = FrameStats { frames: 2, ..Default::default() };
        assert!(script.after_frame(&stats).is_empty());
        stats.frames = 3;
        let actions = script.after_frame(&stats);
        assert!(matches!(&actions[..], [Action::Screenshot { fatal: true, .. }, Action::Quit { report: true }]));
    }
}
