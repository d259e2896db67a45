//! The live channel: status, console and events to every page; commands from the one page
//! that controls the machine, except Hold, Stop and Reset, which any page may give (only
//! starting and moving need control). A page that goes away releases control and nothing
//! else: the job runs on.

use crate::state::lock;
use crate::{auth, AppState};
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::State;
use axum::response::Response;
use axum::routing::get;
use axum::Router;
use futures_util::{SinkExt, StreamExt};
use oficina_app::JobRequest;
use oficina_machine::Command;
use serde::Deserialize;
use serde_json::json;
use std::sync::Arc;

pub(crate) fn routes(state: Arc<AppState>) -> Router {
    Router::new()
        .route("/ws", get(upgrade))
        .route_layer(axum::middleware::from_fn_with_state(
            state.clone(),
            auth::require_token,
        ))
        .with_state(state)
}

/// Largest command message; programs go to the job folder, not through the socket.
const MESSAGE_LIMIT: usize = 64 * 1024;

async fn upgrade(State(st): State<Arc<AppState>>, ws: WebSocketUpgrade) -> Response {
    ws.max_message_size(MESSAGE_LIMIT)
        .on_upgrade(move |socket| client(st, socket))
}

#[derive(Deserialize)]
#[serde(tag = "cmd", rename_all = "snake_case")]
enum Request {
    TakeControl,
    Connect {
        uri: String,
    },
    Start {
        /// A file of the job folder or a bundled sample.
        file: String,
        from_line: Option<u32>,
        speed: Option<f64>,
    },
    Hold,
    Resume,
    Stop,
    Unlock,
    FeedOverride {
        value: f64,
    },
    Jog {
        delta: [f64; 3],
        feed: f64,
    },
    /// Continuous jog: moves along `direction` until `jog_stop` (or this page is lost).
    JogStart {
        direction: [f64; 3],
        feed: f64,
    },
    JogStop,
    SpindleOverride {
        value: f64,
    },
    Home,
    Zero {
        axes: [bool; 3],
    },
    /// A typed line (G-code or a `$` command).
    Mdi {
        line: String,
    },
    /// Ctrl-X.
    SoftReset,
    /// G54 (0) … G59 (5).
    SelectSystem {
        system: usize,
    },
    /// To the active system's zero: Z to a clearance, XY, then Z0 when `z`.
    GoToZero {
        z: bool,
    },
    /// Read the work offsets again (`$#`).
    ReadOffsets,
    /// A macro of the job folder's `macros.json`, by name.
    RunMacro {
        name: String,
    },
    // Probing, tool change and levelling (crate::probing reads them; the session runs them).
    ProbeZPlate(crate::probing::ZPlateArgs),
    ProbeCorner(crate::probing::CornerArgs),
    ProbeSetter(crate::probing::SetterArgs),
    ToolChange(crate::probing::ToolChangeArgs),
    ProbeMap(crate::probing::LevelArgs),
    LoadMap,
    StartLevelled {
        file: String,
        from_line: Option<u32>,
    },
}

impl Request {
    /// Any page may stop the machine: these need no control.
    fn stops(&self) -> bool {
        matches!(self, Request::Hold | Request::Stop | Request::SoftReset)
    }
}

async fn client(st: Arc<AppState>, socket: WebSocket) {
    let me = st.new_client();
    let controls = {
        let mut c = lock(&st.controller);
        if c.is_none() {
            *c = Some(me);
        }
        *c == Some(me)
    };
    let mut live = st.live.subscribe();
    let (mut tx, mut rx) = socket.split();
    let history: Vec<String> = lock(&st.console).iter().cloned().collect();
    let hello = [
        json!({"type": "hello", "client": me, "controller": controls}),
        json!({"type": "console", "lines": history}),
        st.snapshot_json(),
    ];
    for m in hello {
        if tx.send(Message::Text(m.to_string().into())).await.is_err() {
            return release(&st, me);
        }
    }
    if controls {
        announce_control(&st);
    }
    loop {
        tokio::select! {
            out = live.recv() => match out {
                Ok(text) => {
                    if tx.send(Message::Text(text.into())).await.is_err() {
                        break;
                    }
                }
                // A slow page skips status it could not keep up with.
                Err(tokio::sync::broadcast::error::RecvError::Lagged(_)) => continue,
                Err(_) => break,
            },
            inc = rx.next() => match inc {
                Some(Ok(Message::Text(text))) => {
                    let reply = handle(&st, me, &text).await;
                    if tx.send(Message::Text(reply.to_string().into())).await.is_err() {
                        break;
                    }
                }
                Some(Ok(Message::Close(_))) | None | Some(Err(_)) => break,
                Some(Ok(_)) => {}
            },
        }
    }
    release(&st, me);
}

fn release(st: &AppState, me: u64) {
    let mut c = lock(&st.controller);
    if *c == Some(me) {
        *c = None;
        drop(c);
        // A held jog button whose page is gone must not run on; a job does.
        let _ = st.with_session(|s| s.jog_stop().map_err(|e| e.to_string()));
        announce_control(st);
    }
}

fn announce_control(st: &AppState) {
    let c = *lock(&st.controller);
    let _ = st
        .live
        .send(json!({"type": "control", "controller": c}).to_string());
}

async fn handle(st: &Arc<AppState>, me: u64, text: &str) -> serde_json::Value {
    let req: Request = match serde_json::from_str(text) {
        Ok(r) => r,
        Err(e) => return json!({"type": "error", "message": format!("bad command: {e}")}),
    };
    if let Request::TakeControl = req {
        *lock(&st.controller) = Some(me);
        announce_control(st);
        return json!({"type": "ok", "cmd": "take_control", "controller": me});
    }
    if *lock(&st.controller) != Some(me) && !req.stops() {
        return json!({"type": "error", "message": "another page controls the machine: this one watches (take control to act)"});
    }
    let st2 = st.clone();
    let result = tokio::task::spawn_blocking(move || run(&st2, req))
        .await
        .unwrap_or_else(|e| Err(e.to_string()));
    match result {
        Ok(what) => json!({"type": "ok", "cmd": what}),
        Err(message) => json!({"type": "error", "message": message}),
    }
}

fn run(st: &Arc<AppState>, req: Request) -> Result<&'static str, String> {
    let cmd = |c: Command| st.with_session(|s| s.command(c).map_err(|e| e.to_string()));
    match req {
        Request::TakeControl => Ok("take_control"),
        Request::Connect { uri } => st
            .connect(&crate::profiles::machine_uri(st, &uri)?)
            .map(|()| "connect"),
        Request::Start {
            file,
            from_line,
            speed,
        } => {
            let text = crate::api::program_text(st, &file).map_err(|(_, m)| m)?;
            // The virtual machine runs with the page's saved tool table (real firmware keeps
            // its own).
            let tools = crate::profiles::saved_tools(st)?;
            st.with_session(|s| match s.profile() {
                Some(_) => s.set_tools(tools).map_err(|e| e.to_string()),
                None => Ok(()),
            })?;
            st.start(JobRequest {
                name: file,
                text,
                from_line,
                speed,
            })
            .map(|()| "start")
        }
        Request::Hold => cmd(Command::Hold).map(|()| "hold"),
        Request::Resume => cmd(Command::Resume).map(|()| "resume"),
        Request::Stop => cmd(Command::Stop).map(|()| "stop"),
        Request::Unlock => cmd(Command::Unlock).map(|()| "unlock"),
        Request::FeedOverride { value } => {
            cmd(Command::FeedOverride(value)).map(|()| "feed_override")
        }
        Request::Jog { delta, feed } => cmd(Command::Jog { delta, feed }).map(|()| "jog"),
        Request::JogStart { direction, feed } => st
            .with_session(|s| s.jog_start(direction, feed).map_err(|e| e.to_string()))
            .map(|()| "jog_start"),
        Request::JogStop => cmd(Command::JogCancel).map(|()| "jog_stop"),
        Request::SpindleOverride { value } => {
            cmd(Command::SpindleOverride(value)).map(|()| "spindle_override")
        }
        Request::Home => crate::probing::home(st).map(|()| "home"),
        Request::Zero { axes } => st
            .with_session(|s| s.zero(axes).map_err(|e| e.to_string()))
            .map(|()| "zero"),
        Request::Mdi { line } => {
            let reply = st.with_session(|s| s.mdi(&line).map_err(|e| e.to_string()))?;
            reply.console_lines().iter().for_each(|l| st.say(l));
            Ok("mdi")
        }
        Request::SoftReset => st
            .with_session(|s| s.soft_reset().map_err(|e| e.to_string()))
            .map(|()| "soft_reset"),
        Request::SelectSystem { system } => st
            .with_session(|s| s.select_system(system).map_err(|e| e.to_string()))
            .map(|()| "select_system"),
        Request::GoToZero { z } => st
            .with_session(|s| s.go_to_zero(z).map_err(|e| e.to_string()))
            .map(|()| "go_to_zero"),
        Request::ReadOffsets => st
            .with_session(|s| s.read_offsets().map_err(|e| e.to_string()))
            .map(|()| "read_offsets"),
        Request::RunMacro { name } => {
            let text = crate::macros::macro_text(st, &name)?;
            st.say(&format!("macro {name}"));
            let replies = st.with_session(|s| s.run_macro(&text).map_err(|e| e.to_string()))?;
            for r in &replies {
                r.console_lines().iter().for_each(|l| st.say(l));
            }
            match replies.iter().find_map(|r| r.error.as_ref()) {
                Some(e) => Err(format!("macro {name} stopped: {e}")),
                None => Ok("run_macro"),
            }
        }
        Request::ProbeZPlate(a) => crate::probing::z_plate(st, a).map(|()| "probe_z_plate"),
        Request::ProbeCorner(a) => crate::probing::corner(st, a).map(|()| "probe_corner"),
        Request::ProbeSetter(a) => crate::probing::setter(st, a).map(|()| "probe_setter"),
        Request::ToolChange(a) => crate::probing::tool_change(st, a).map(|()| "tool_change"),
        Request::ProbeMap(a) => crate::probing::probe_map(st, a).map(|()| "probe_map"),
        Request::LoadMap => crate::probing::load(st).map(|()| "load_map"),
        Request::StartLevelled { file, from_line } => {
            crate::probing::start_levelled(st, file, from_line).map(|()| "start_levelled")
        }
    }
}
