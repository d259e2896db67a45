//! `cargo run -p oficina-stitch --example render -- DESIGN.jef OUT.png [DPI]`: an embroidery
//! file rendered as thread (how `docs/embroidery/*.png` were made).

fn main() {
    let a: Vec<String> = std::env::args().collect();
    if a.len() < 3 {
        eprintln!("usage: render DESIGN OUT.png [DPI]");
        std::process::exit(2);
    }
    let bytes = std::fs::read(&a[1]).expect("reading the design");
    let format = oficina_stitch::Format::sniff(&bytes)
        .or_else(|| oficina_stitch::Format::from_path(std::path::Path::new(&a[1])))
        .expect("not an embroidery file");
    let plan = format.read(&bytes, "design").expect("reading the design");
    let o = oficina_stitch::RenderOptions {
        dpi: a.get(3).map_or(254.0, |d| d.parse().expect("dpi")),
        ..Default::default()
    };
    let t = std::time::Instant::now();
    let r = oficina_stitch::render(&plan, &o).expect("render");
    let png = r.png();
    std::fs::write(&a[2], png).expect("writing");
    println!(
        "{}: {}x{} px at {:.0} dpi in {:.3} s",
        a[2],
        r.width,
        r.height,
        r.dpi,
        t.elapsed().as_secs_f64()
    );
}
