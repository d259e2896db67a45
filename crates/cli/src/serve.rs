//! `oficina serve`: the web workbench on this computer (or, with a token, on a network).

use anyhow::Context;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// Port on 127.0.0.1 (0: any free port).
    #[arg(long, default_value_t = 7878)]
    port: u16,
    /// Listen on ADDR:PORT instead; an address beyond this computer needs --token.
    #[arg(long)]
    listen: Option<SocketAddr>,
    /// Secret the page and the API must present (`?token=…` or `Authorization: Bearer …`).
    #[arg(long, env = "OFICINA_TOKEN")]
    token: Option<String>,
    /// The machine: `virtual` (or `virtual:PROFILE`), `grbl:/dev/ttyUSB0`, `tcp://HOST:PORT`.
    #[arg(long, default_value = "virtual")]
    machine: String,
    /// Folder of uploads and generated programs (nothing outside it is written).
    #[arg(long, default_value = "oficina-jobs")]
    jobs: PathBuf,
    /// Serve the page from this folder (development: web/dist) instead of the one built
    /// into the binary.
    #[arg(long, env = "OFICINA_WEB_DIR")]
    web: Option<PathBuf>,
    /// Largest upload, MB.
    #[arg(long, default_value_t = 256)]
    upload_mb: usize,
    /// A program (in the job folder, or a bundled sample name) the page opens with.
    #[arg(long)]
    open: Option<String>,
    /// Another name the page may be opened by (repeatable): `NAME` on the server's port, or
    /// `NAME:PORT` behind a proxy. Any other `Host:` is refused (DNS rebinding).
    #[arg(long = "allow-host", value_name = "NAME[:PORT]")]
    allow_host: Vec<String>,
}

pub(crate) fn run(args: Args) -> anyhow::Result<ExitCode> {
    let addr = args
        .listen
        .unwrap_or(SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), args.port));
    let web = args.web;
    if web.is_none() && !oficina_server::page_built() {
        eprintln!("(this oficina was built before the page: run `npm ci && npm run build` in web/ and rebuild, or give --web web/dist; the API works meanwhile)");
    }
    let token = args.token.clone();
    let config = oficina_server::Config {
        addr,
        token: args.token,
        job_dir: args.jobs,
        web_dir: web,
        machine: args.machine,
        upload_limit: args.upload_mb.saturating_mul(1 << 20),
        open: args.open,
        allowed_hosts: args.allow_host,
    };
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .context("starting the server runtime")?;
    rt.block_on(oficina_server::serve(config, |a| {
        let query = token.map(|t| format!("?token={t}")).unwrap_or_default();
        println!("oficina workbench: http://{a}/{query}");
    }))
    .map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(ExitCode::SUCCESS)
}
