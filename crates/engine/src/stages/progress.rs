//! A progress bar with an ETA for terminal users (indicatif); the CLI only creates it when stderr is a terminal.

use indicatif::{ProgressBar, ProgressStyle};
use prism_core::settings::RenderSettings;

/// The terminal progress bar of one render.
pub struct ProgressReporter {
    bar: ProgressBar,
    by_time: bool,
}

impl ProgressReporter {
    /// A bar counting samples per pixel up to `spp`, or tenths of seconds up to the time budget when only that
    /// bounds the render (passes when neither does).
    pub fn new(s: &RenderSettings) -> Self {
        // Track samples when the sample count bounds the render, seconds when only the time budget does.
        let (len, by_time) = match (s.spp, s.time_budget) {
            (Some(spp), _) => (spp as u64, false),
            (None, Some(t)) => ((t * 10.0).ceil() as u64, true),
            (None, None) => (s.passes as u64, false),
        };
        let bar = ProgressBar::new(len);
        let template = if by_time {
            "{spinner} [{elapsed_precise}] {bar:40} {msg}"
        } else {
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} spp  ETA {eta}  {msg}"
        };
        bar.set_style(ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()));
        ProgressReporter { bar, by_time }
    }

    /// `note` is the integrator's own progress (e.g. iterations and photons of a photon mapper).
    pub fn update(&self, passes: u32, spp: u64, elapsed_s: f64, note: Option<&str>) {
        let note = note.map(|n| format!(", {n}")).unwrap_or_default();
        if self.by_time {
            self.bar.set_position((elapsed_s * 10.0) as u64);
            self.bar.set_message(format!("{spp} spp, pass {passes}{note}"));
        } else {
            self.bar.set_position(spp);
            self.bar.set_message(format!("pass {passes}{note}"));
        }
    }

    /// Remove the bar from the terminal.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
