//! The file written is the format asked for, and a machine profile's name means the same
//! from any folder (issue #21, items 6 and 7).

mod common;

use common::{oficina_in, root, text};

#[test]
fn an_output_a_command_cannot_write_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let plate = root().join("samples/mill/plate.svg");
    let dome = root().join("samples/relief/dome.png");
    let house = root().join("samples/plot/house.plt");
    let points = root().join("samples/sole/size34.csv");
    let a_file = d.join("taken");
    std::fs::write(&a_file, "x").unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        // The input does not even exist: the output is refused first.
        (
            vec!["mill", "no-such.svg", "--op", "pocket", "--depth", "1", "-o", "part.dxf"],
            "-o part.dxf: oficina mill cannot write .dxf files here; it writes G-code programs: .nc, .ngc",
        ),
        (
            vec!["mill", plate.to_str().unwrap(), "--op", "pocket", "--depth", "1", "-o", "p.svg"],
            "cannot write .svg files",
        ),
        (
            vec!["carve", dome.to_str().unwrap(), "--pixel-size", "0.5", "--depth", "2", "-o", "c.png"],
            "oficina carve cannot write .png",
        ),
        (
            vec!["plot", house.to_str().unwrap(), "--machine", "pen-plotter", "-o", "h.plt"],
            "oficina plot cannot write .plt files here; it writes G-code programs",
        ),
        (
            vec!["plot", house.to_str().unwrap(), "--machine", "pen-plotter", "--format", "hpgl", "-o", "h.nc"],
            "it writes HPGL: .hpgl, .plt",
        ),
        (
            vec!["sole", points.to_str().unwrap(), "--from-size", "34", "--to-size", "36", "-o", a_file.to_str().unwrap()],
            "writes a folder of programs, and this is a file",
        ),
    ]
    .into_iter()
    .map(|(a, w)| (a.into_iter().map(String::from).collect(), w))
    .collect();
    for (args, want) in &cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let run = oficina_in(d, &args);
        let (_, err) = text(&run);
        assert_eq!(run.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: want '{want}' in {err}");
    }
    // Nothing was written: no program, preview or stock picture.
    let mut left: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["taken"]);
}

#[test]
fn profile_names_are_bundled_from_any_folder_and_paths_stay_paths() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let plate = root().join("samples/mill/plate.svg");
    let out = d.join("p.nc");
    let mill = |extra: &[&str]| {
        let mut args = vec![
            "mill",
            plate.to_str().unwrap(),
            "--op",
            "profile-out",
            "--depth",
            "1",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let run = oficina_in(d, &args);
        let (stdout, stderr) = text(&run);
        assert!(run.status.success(), "{extra:?}: {stderr}");
        stdout
    };
    // The default and the name, from a folder with no profiles/ in it.
    for extra in [&[][..], &["--profile", "grbl-router"]] {
        let stdout = mill(extra);
        assert!(stdout.contains("(planner"), "{extra:?}: {stdout}");
    }
    // The old default, a path relative to the checkout, is a path: here it is missing, and
    // the report says which bundled name to use instead.
    let stdout = mill(&["--profile", "profiles/grbl-router.toml"]);
    assert!(
        stdout.contains("no such profile file (the bundled profile of that name is `grbl-router`"),
        "{stdout}"
    );
    // sole too, from the same folder.
    let points = root().join("samples/sole/size34.csv");
    let run = oficina_in(
        d,
        &[
            "sole",
            points.to_str().unwrap(),
            "--from-size",
            "34",
            "--to-size",
            "35",
            "--check-pixel",
            "2",
            "-o",
            d.join("sole").to_str().unwrap(),
        ],
    );
    let (stdout, stderr) = text(&run);
    assert!(run.status.success(), "{stderr}");
    assert!(stdout.contains("(planner"), "{stdout}");
}

#[test]
fn mill_never_writes_over_its_drawing_and_says_what_stayed_open() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A square of four paths whose corner at (50, 10) misses by 0.05 mm.
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" viewBox="0 0 100 100">
<path d="M 10 10 L 50 10"/><path d="M 50 50 L 50.05 10"/><path d="M 50 50 L 10 50"/><path d="M 10 50 L 10 10"/></svg>"#;
    let part = d.join("part.svg");
    std::fs::write(&part, svg).unwrap();
    let mill = |out: &str, extra: &[&str]| {
        let mut args = vec![
            "mill",
            "part.svg",
            "--op",
            "profile-out",
            "--depth",
            "1",
            "-o",
            out,
        ];
        args.extend_from_slice(extra);
        oficina_in(d, &args)
    };
    // An output that is the drawing itself is refused, the drawing intact.
    let run = mill("part.nc", &["--preview", "part.svg"]);
    let (_, err) = text(&run);
    assert_eq!(run.status.code(), Some(1), "{err}");
    assert!(err.contains("part.svg is the input drawing"), "{err}");
    assert_eq!(std::fs::read_to_string(&part).unwrap(), svg);
    assert!(!d.join("part.nc").exists());
    // -o part.nc's preview would be part.svg, the drawing: it goes to part.preview.svg.
    let run = mill("part.nc", &["--join-tol", "0.1"]);
    let (_, err) = text(&run);
    assert!(run.status.success(), "{err}");
    assert_eq!(std::fs::read_to_string(&part).unwrap(), svg);
    assert!(d.join("part.preview.svg").exists());
    std::fs::remove_file(d.join("part.nc")).unwrap();
    // Nothing closed at the default tolerance: the error says what stayed open, where, and
    // the tolerance that joins it.
    let run = mill("x.nc", &[]);
    let (_, err) = text(&run);
    assert_eq!(run.status.code(), Some(1), "{err}");
    assert!(err.contains("nothing to cut"), "{err}");
    assert!(
        err.contains("open on layer svg: 1 path, largest gap 0.050 mm at (50.000, 90.000)"),
        "{err}"
    );
    assert!(
        err.contains("--join-tol 0.050 would join the nearest"),
        "{err}"
    );
    // That tolerance does: one loop chained from the four paths.
    let run = mill("x.nc", &["--join-tol", "0.05"]);
    let (out, err) = text(&run);
    assert!(run.status.success(), "{err}");
    assert!(
        out.contains("imported: 1 closed loop: 0 closed in the file, 0 closed where their ends meet, 1 chained from 4 pieces (join tolerance 0.05 mm)"),
        "{out}"
    );
    // Out of range is refused by name.
    let (_, err) = text(&mill("x.nc", &["--join-tol", "11"]));
    assert!(err.contains("--join-tol 11: use 0 to 10"), "{err}");
}
