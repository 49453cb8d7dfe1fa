//! The live viewer: `dieface view FILE.die` and `dieface watch FILE.die --serve`.
//!
//! A page served on 127.0.0.1 shows the last good model of the script and follows every
//! save. The watch loop publishes each build here ([`Viewer::publish_model`],
//! [`Viewer::publish_errors`]); the HTTP server ([`http`]) hands the page the latest of
//! them and tells it of each new one through a server-sent event stream, so the page
//! swaps the model in place (the camera stays) or lays the diagnostic over the model it
//! has. The page and its three.js are embedded in the binary ([`assets`]): the viewer
//! works offline.
//!
//! What the page reads:
//!
//! | path | what |
//! |---|---|
//! | `/` | the page (`page/index.html`, `viewer.js`, `viewer.css`) |
//! | `/vendor/three/...` | three.js, pinned (`package.json`), with its licence |
//! | `/events` | server-sent events: the status (below) at connection and after each build |
//! | `/status.json` | `{version, model_version, state: building|ok|error, took_ms, reran, error}` |
//! | `/model.glb` | the last good model, the bytes `dieface build -o x.glb` writes |
//! | `/info.json` | its declarations: kind, name, line, quality figures |
//! | `/piece.json?name=binder/front` | one piece's kind, line and shape summary |
//! | `/seams.json` | the normal jump along the seams (analysis mode) |

mod assets;
mod http;

use std::net::SocketAddr;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Duration;

use serde_json::json;

use crate::die::model::Part;
use crate::export::scene::Scene;

pub(crate) use http::serve;

/// The port `--port` defaults to.
pub(crate) const DEFAULT_PORT: u16 = 4173;

/// A running viewer: where it listens, and the state its pages read.
#[derive(Clone)]
pub(crate) struct Viewer {
    shared: Arc<Shared>,
    /// The address the server listens on (127.0.0.1 and the port it got).
    pub addr: SocketAddr,
}

/// The published state and the signal that wakes the event streams.
#[derive(Default)]
struct Shared {
    state: Mutex<Published>,
    changed: Condvar,
}

/// What the page can read: the last good model and the status of the last build.
#[derive(Default)]
struct Published {
    /// Counts every publication (build started, model, errors): the event streams send
    /// the status whenever it moves.
    version: u64,
    /// The `version` of the model being served (0: none yet).
    model_version: u64,
    /// The status as JSON (see the module table).
    status: String,
    /// The model as GLB.
    glb: Arc<Vec<u8>>,
    /// `/info.json` of the model.
    info: Arc<String>,
    /// The tessellated model and the die model's parts, for `/seams.json` and
    /// `/piece.json`.
    scene: Option<Arc<Scene>>,
    parts: Option<Arc<Vec<Part>>>,
    /// `/seams.json` of the model, made at the first request.
    seams: Option<Arc<String>>,
}

impl Shared {
    /// The state, even if a thread panicked while holding it (the state is replaced
    /// whole at each publication, so it is never half-written).
    fn lock(&self) -> MutexGuard<'_, Published> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Moves the state on with `f` and wakes every event stream.
    fn update(&self, f: impl FnOnce(&mut Published)) {
        let mut s = self.lock();
        s.version += 1;
        f(&mut s);
        drop(s);
        self.changed.notify_all();
    }

    /// The status and its version once the version differs from `seen`, or `None`
    /// after `timeout` without a change.
    fn wait_status(&self, seen: u64, timeout: Duration) -> Option<(u64, String)> {
        let guard = self.lock();
        let (guard, _) = self
            .changed
            .wait_timeout_while(guard, timeout, |s| s.version == seen)
            .unwrap_or_else(|e| e.into_inner());
        (guard.version != seen).then(|| (guard.version, guard.status.clone()))
    }
}

impl Viewer {
    /// Says a build has started (the page shows it is rebuilding).
    pub(crate) fn building(&self) {
        self.shared.update(|s| {
            s.status = status(s.version, s.model_version, "building", None, &[], None);
        });
    }

    /// Publishes a clean build's model: its GLB, its `/info.json`, its scene and the die
    /// model's parts, and how long the build took from the save.
    pub(crate) fn publish_model(
        &self,
        glb: Vec<u8>,
        info: String,
        scene: Scene,
        parts: Vec<Part>,
        took: Duration,
        reran: &[String],
    ) {
        self.shared.update(|s| {
            if s.model_version > 0 && *s.glb == glb {
                // An edit that changed nothing drawn (a comment, a figure): the page
                // keeps its model and only hears the build went well.
                s.status = status(s.version, s.model_version, "ok", Some(took), reran, None);
                return;
            }
            s.model_version = s.version;
            s.glb = Arc::new(glb);
            s.info = Arc::new(info);
            s.scene = Some(Arc::new(scene));
            s.parts = Some(Arc::new(parts));
            s.seams = None;
            s.status = status(s.version, s.model_version, "ok", Some(took), reran, None);
        });
    }

    /// Publishes a failed build: the diagnostics as text over the model the page has.
    pub(crate) fn publish_errors(&self, text: String, took: Duration) {
        self.shared.update(|s| {
            s.status = status(
                s.version,
                s.model_version,
                "error",
                Some(took),
                &[],
                Some(&text),
            );
        });
    }
}

/// The status JSON of the module table.
fn status(
    version: u64,
    model_version: u64,
    state: &str,
    took: Option<Duration>,
    reran: &[String],
    error: Option<&str>,
) -> String {
    json!({
        "version": version,
        "model_version": model_version,
        "state": state,
        "took_ms": took.map(|t| (t.as_secs_f64() * 1e4).round() / 10.0),
        "reran": reran,
        "error": error,
    })
    .to_string()
}
