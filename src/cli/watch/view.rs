//! What the viewer shows, shared between the render loop (which publishes) and the server's threads (which wait
//! for news): the latest frame (linear RGB and sample counts after a pass), the last scene error, and a version
//! number that every change increments. Server-Sent Events carry [`View::event_json`]; `/frame.bin` the frame.

use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Duration;

/// One image after a pass.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Linear RGB per pixel, row-major from the top left.
    pub rgb: Vec<f32>,
    /// Samples per pixel.
    pub counts: Vec<u32>,
    /// Passes done.
    pub pass: u32,
    /// Samples per pixel done.
    pub spp: u64,
    /// Seconds of rendering since the render started.
    pub seconds: f64,
    /// The film's estimated relMSE, when the render has a noise target or two passes to estimate it from.
    pub noise: Option<f64>,
    /// The scene's PNG exposure in stops (the viewer's initial slider position).
    pub exposure: f32,
}

impl Frame {
    /// The frame as `/frame.bin` sends it: little-endian `f32` RGB for every pixel, then a `u32` count per pixel.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.rgb.len() * 4 + self.counts.len() * 4);
        for v in &self.rgb {
            out.extend_from_slice(&v.to_le_bytes());
        }
        for c in &self.counts {
            out.extend_from_slice(&c.to_le_bytes());
        }
        out
    }

    /// The frame as an image (for the PNG and EXR downloads).
    pub fn image(&self) -> prism_core::io::Image {
        let pixels = self.rgb.chunks_exact(3).map(|c| glam::Vec3::new(c[0], c[1], c[2])).collect();
        prism_core::io::Image::new(self.width, self.height, pixels)
    }
}

/// The viewer's state.
#[derive(Clone, Debug, Default)]
pub struct View {
    /// Incremented by every change.
    pub version: u64,
    /// The latest image (kept when a reload fails, so the error shows over the last good image).
    pub frame: Option<Arc<Frame>>,
    /// The scene error of the last reload, one line (`file:line:column: message`).
    pub error: Option<String>,
    /// What the renderer is doing: `loading`, `rendering`, `done`.
    pub status: &'static str,
    /// The scene file.
    pub scene: String,
}

impl View {
    /// The Server-Sent Event's JSON for this state.
    pub fn event_json(&self) -> String {
        let f = self.frame.as_deref();
        serde_json::json!({
            "version": self.version,
            "status": self.status,
            "scene": self.scene,
            "error": self.error,
            "width": f.map(|f| f.width),
            "height": f.map(|f| f.height),
            "pass": f.map(|f| f.pass),
            "spp": f.map(|f| f.spp),
            "seconds": f.map(|f| f.seconds),
            "noise": f.and_then(|f| f.noise),
            "exposure": f.map(|f| f.exposure),
        })
        .to_string()
    }
}

/// The view and the condition variable its readers wait on.
#[derive(Default)]
pub struct Shared {
    view: Mutex<View>,
    changed: Condvar,
}

impl Shared {
    /// Lock the view (a poisoned lock still holds a usable view: the writer only assigns fields).
    pub fn lock(&self) -> MutexGuard<'_, View> {
        self.view.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Change the view and wake every reader.
    pub fn update(&self, f: impl FnOnce(&mut View)) {
        let mut v = self.lock();
        f(&mut v);
        v.version += 1;
        drop(v);
        self.changed.notify_all();
    }

    /// Wait until the view's version differs from `seen` or `timeout` passes; the view then.
    pub fn wait_change(&self, seen: u64, timeout: Duration) -> View {
        let v = self.lock();
        let (v, _) =
            self.changed.wait_timeout_while(v, timeout, |v| v.version == seen).unwrap_or_else(|e| e.into_inner());
        v.clone()
    }
}
