//! A developer's probe: `OFICINA_NGC=file cargo test -p oficina-gcode --test interp_dev -- --ignored --nocapture`
//! prints the program's canon in rs274's text.

#[path = "interp_support.rs"]
mod support;

#[test]
#[ignore]
fn print_file_as_rs274() {
    let Ok(path) = std::env::var("OFICINA_NGC") else {
        return;
    };
    let text = std::fs::read_to_string(path).unwrap();
    let tools = if std::env::var("OFICINA_TBL").is_ok() {
        support::corpus_tools()
    } else {
        Default::default()
    };
    let r = support::run_with(
        &text,
        oficina_gcode::Dialect::LinuxCnc,
        tools,
        Default::default(),
    );
    let mut p = oficina_gcode::Rs274Printer::new();
    let mut out = std::io::stdout();
    for c in &r.ops {
        p.print(c, &mut out).unwrap();
    }
    for e in &r.errors {
        println!("ERROR {e} {:?}", e.help);
    }
}
