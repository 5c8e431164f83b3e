//! The files a watched scene is made of: the scene file and every file its last load read (meshes, textures,
//! environment maps, glTF buffers: `Resources::inputs`). Their directories are watched (`notify`), not the files,
//! since editors save by writing a new file and renaming it over the old one; an event counts when it names one of
//! the files. A change raises the current render's cancel flag at once, so the pass in flight stops, and records
//! when it happened, for the debounce and the restart latency.

use notify::{RecommendedWatcher, RecursiveMode, Watcher};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// What the watcher thread and the render loop share.
#[derive(Default)]
pub struct Changes {
    /// The files that count, canonical.
    files: Mutex<BTreeSet<PathBuf>>,
    /// The current render's cancel flag.
    cancel: Mutex<Option<Arc<AtomicBool>>>,
    /// When the first change not yet taken happened, and the last one.
    pending: Mutex<Option<(Instant, Instant)>>,
}

impl Changes {
    /// Take the changes seen so far: `(first, last)`.
    pub fn take(&self) -> Option<(Instant, Instant)> {
        self.pending.lock().unwrap_or_else(|e| e.into_inner()).take()
    }

    /// The time of the last change, without taking it.
    pub fn last(&self) -> Option<Instant> {
        self.pending.lock().unwrap_or_else(|e| e.into_inner()).map(|(_, l)| l)
    }

    /// Cancel this render when a file changes.
    pub fn set_cancel(&self, flag: Arc<AtomicBool>) {
        *self.cancel.lock().unwrap_or_else(|e| e.into_inner()) = Some(flag);
    }

    fn changed(&self, paths: &[PathBuf]) {
        let files = self.files.lock().unwrap_or_else(|e| e.into_inner());
        let hit = paths.iter().any(|p| files.contains(p) || canonical(p).is_some_and(|c| files.contains(&c)));
        drop(files);
        if !hit {
            return;
        }
        let now = Instant::now();
        let mut pending = self.pending.lock().unwrap_or_else(|e| e.into_inner());
        *pending = Some(pending.map_or((now, now), |(first, _)| (first, now)));
        drop(pending);
        if let Some(c) = &*self.cancel.lock().unwrap_or_else(|e| e.into_inner()) {
            c.store(true, Ordering::Relaxed);
        }
    }
}

/// A path made absolute and canonical where it exists; its directory's canonical form joined with its name where it
/// does not (a file being replaced).
fn canonical(p: &Path) -> Option<PathBuf> {
    if let Ok(c) = p.canonicalize() {
        return Some(c);
    }
    let dir = p.parent()?.canonicalize().ok()?;
    Some(dir.join(p.file_name()?))
}

/// The file watcher: owns the `notify` watcher and the directories it watches.
pub struct FileWatcher {
    watcher: RecommendedWatcher,
    dirs: BTreeSet<PathBuf>,
    /// Shared with the watcher's callback.
    pub changes: Arc<Changes>,
}

impl FileWatcher {
    /// A watcher with nothing watched yet.
    pub fn new() -> anyhow::Result<Self> {
        let changes = Arc::new(Changes::default());
        let c = changes.clone();
        let watcher = notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
            if let Ok(e) = event
                && !matches!(e.kind, notify::EventKind::Access(_))
            {
                c.changed(&e.paths);
            }
        })
        .map_err(|e| anyhow::anyhow!("prism watch: cannot watch files: {e}"))?;
        Ok(FileWatcher { watcher, dirs: BTreeSet::new(), changes })
    }

    /// Watch `files` as well as those watched already (after a load that failed part way, whose list is short).
    pub fn watch_more(&mut self, files: &[PathBuf]) {
        let mut all: Vec<PathBuf> =
            self.changes.files.lock().unwrap_or_else(|e| e.into_inner()).iter().cloned().collect();
        all.extend(files.iter().cloned());
        self.watch(&all);
    }

    /// Watch exactly `files` from now on (their directories; files that do not exist are watched for creation).
    pub fn watch(&mut self, files: &[PathBuf]) {
        let files: BTreeSet<PathBuf> = files.iter().filter_map(|f| canonical(f)).collect();
        let dirs: BTreeSet<PathBuf> = files.iter().filter_map(|f| f.parent().map(Path::to_path_buf)).collect();
        for gone in self.dirs.difference(&dirs) {
            let _ = self.watcher.unwatch(gone);
        }
        for new in dirs.difference(&self.dirs) {
            if let Err(e) = self.watcher.watch(new, RecursiveMode::NonRecursive) {
                eprintln!("warning: prism watch: cannot watch {}: {e}", new.display());
            }
        }
        self.dirs = dirs;
        *self.changes.files.lock().unwrap_or_else(|e| e.into_inner()) = files;
    }
}
