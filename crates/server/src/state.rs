//! What the server holds: the machine session, the job's text, the console, who controls,
//! and the channel that carries live status to every page.

use oficina_app::{JobRequest, Session, SessionEvent};
use serde_json::json;
use std::collections::VecDeque;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;
use tokio::sync::broadcast;

/// How the server was started (`oficina serve`'s flags).
pub struct Config {
    /// Address and port the server listens on.
    pub addr: SocketAddr,
    /// The token every API request must carry; `None`: no token asked (loopback only).
    pub token: Option<String>,
    /// Uploads and generated programs live here and only here.
    pub job_dir: PathBuf,
    /// The built page (web/dist); `None` serves a page that says how to build it.
    pub web_dir: Option<PathBuf>,
    /// The machine URI connected at start (`virtual` by default).
    pub machine: String,
    /// Largest upload or program body, bytes.
    pub upload_limit: usize,
    /// The program the page opens with: a file in the job folder or a bundled sample name.
    pub open: Option<String>,
    /// Names besides the listening address that `Host:` may carry (`--allow-host`): `name`
    /// on the server's port, or `name:port` (behind a proxy).
    pub allowed_hosts: Vec<String>,
}

/// The job the machine runs, kept so a page that reconnects shows it where it is.
#[derive(Clone)]
pub struct RunningJob {
    /// The program's file name, as the page shows it.
    pub name: String,
    /// The program text the machine runs.
    pub text: Arc<String>,
}

/// Everything the server's handlers share.
pub struct AppState {
    /// How the server was started.
    pub config: Config,
    session: Mutex<Option<Session>>,
    /// The job the machine runs or last ran.
    pub job: Mutex<Option<RunningJob>>,
    /// The console's recent lines, sent to a page that joins.
    pub console: Mutex<VecDeque<String>>,
    /// The client allowed to move the machine; every other page watches.
    pub controller: Mutex<Option<u64>>,
    next_client: AtomicU64,
    /// Status, console and job events to every connected page (JSON text).
    pub live: broadcast::Sender<String>,
    /// The CAM job being computed, if any (cancelled through `/api/cancel`).
    pub computing: crate::jobs::Computing,
}

/// Lines of console history a new page receives.
const CONSOLE_LINES: usize = 300;
/// Status is sent this often: smooth for the eye, light for the link.
const STATUS_PERIOD: Duration = Duration::from_millis(100);

pub(crate) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl AppState {
    /// Opens the job folder and connects the configured machine.
    pub fn new(config: Config) -> Result<Arc<AppState>, String> {
        std::fs::create_dir_all(&config.job_dir).map_err(|e| {
            format!(
                "cannot create the job folder {}: {e}",
                config.job_dir.display()
            )
        })?;
        let session = Session::open(&config.machine).map_err(|e| e.to_string())?;
        let (live, _) = broadcast::channel(256);
        Ok(Arc::new(AppState {
            config,
            session: Mutex::new(Some(session)),
            job: Mutex::new(None),
            console: Mutex::new(VecDeque::new()),
            controller: Mutex::new(None),
            next_client: AtomicU64::new(1),
            live,
            computing: Default::default(),
        }))
    }

    /// A number for a newly connected page.
    pub fn new_client(&self) -> u64 {
        self.next_client.fetch_add(1, Ordering::Relaxed)
    }

    /// Run `f` on the session, or say there is no machine.
    pub fn with_session<T>(
        &self,
        f: impl FnOnce(&mut Session) -> Result<T, String>,
    ) -> Result<T, String> {
        match lock(&self.session).as_mut() {
            Some(s) => f(s),
            None => Err("no machine connected".into()),
        }
    }

    /// Replace the machine (refused while a job runs: a page must never stop it by accident).
    pub fn connect(&self, uri: &str) -> Result<(), String> {
        let mut guard = lock(&self.session);
        if let Some(s) = guard.as_ref() {
            let state = s.snapshot().state;
            if !matches!(state, "idle" | "alarm") {
                return Err(format!("the machine is busy ({state}): stop the job first"));
            }
        }
        // Opened before the old one is dropped: a bad address leaves the machine as it was.
        *guard = Some(Session::open(uri).map_err(|e| e.to_string())?);
        drop(guard);
        self.say(&format!("connected to {uri}"));
        Ok(())
    }

    /// Starts a job on the machine and remembers it for pages that join later.
    pub fn start(&self, req: JobRequest) -> Result<(), String> {
        let job = RunningJob {
            name: req.name.clone(),
            text: req.text.clone(),
        };
        self.with_session(|s| s.start(req).map_err(|e| e.to_string()))?;
        self.say(&format!("started {}", job.name));
        *lock(&self.job) = Some(job);
        Ok(())
    }

    /// A line on every page's console (and in the history for pages that join later).
    pub fn say(&self, line: &str) {
        let mut c = lock(&self.console);
        if c.len() == CONSOLE_LINES {
            c.pop_front();
        }
        c.push_back(line.to_string());
        drop(c);
        let _ = self
            .live
            .send(json!({"type": "console", "lines": [line]}).to_string());
    }

    /// The machine's status as the live channel's JSON message.
    pub fn snapshot_json(&self) -> serde_json::Value {
        match lock(&self.session).as_ref() {
            Some(s) => json!({"type": "status", "status": s.snapshot()}),
            None => json!({"type": "status", "status": null}),
        }
    }
}

/// The thread that drains machine events and sends status to every page, whether or not any
/// page is open: the job never depends on a browser.
pub(crate) fn spawn_pump(state: Arc<AppState>) {
    std::thread::spawn(move || loop {
        let events = match lock(&state.session).as_mut() {
            Some(s) => s.poll(Duration::ZERO),
            None => Vec::new(),
        };
        for e in events {
            match &e {
                SessionEvent::Message { text } => state.say(text),
                SessionEvent::Alarm { message, meaning } => {
                    state.say(&format!("ALARM: {message} — {meaning}"))
                }
                SessionEvent::JobEnd { completed, seconds } => state.say(&format!(
                    "job {} after {seconds:.1} s of machine time",
                    if *completed { "finished" } else { "stopped" }
                )),
            }
            let _ = state
                .live
                .send(json!({"type": "event", "event": e}).to_string());
        }
        let _ = state.live.send(state.snapshot_json().to_string());
        std::thread::sleep(STATUS_PERIOD);
    });
}
