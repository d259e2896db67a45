//! Item 9 and 10 at library level: the seed's prototype job (size 34 → 40, 2 % shrinkage)
//! on the shipped digitised contour; every program read back by the interpreter, accepted by
//! rs274, and simulated with zero gouge.

mod common;

use common::sole_sample;

use oficina_cam::ops::{sole_job, Part, SoleJob, GOUGE_TOL};
use oficina_geom::{offset_areas, to_ring, Area};
use oficina_post::{program_text, read_back, PostDialect, PostOptions};
use oficina_sim::{check_mill, Design};

#[test]
fn size_34_to_40_insert_and_cavity_for_both_feet() {
    let pts = sole_sample();
    assert!(pts.len() > 20);
    let tread: Vec<oficina_geom::Path> = oficina_io::load_drawing(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../samples/sole/tread.svg"
    )))
    .unwrap()
    .drawing
    .paths()
    .cloned()
    .collect();
    assert_eq!(tread.len(), 4);
    let job = SoleJob {
        tread,
        ..SoleJob::seed(34.0, 40.0)
    };
    let r = sole_job(&pts, &job).unwrap();
    eprintln!(
        "factors {:?}, fit {} blocks {} dev {:.3}, fallback {:?}",
        r.factors, r.fit.method, r.fit.blocks, r.fit.max_deviation, r.fallback
    );
    assert_eq!(r.programs.len(), 4);
    let opts = PostOptions {
        dialect: PostDialect::LinuxCnc,
        allow_m6: false,
        title: "sole".into(),
        settings: vec![],
    };
    for p in &r.programs {
        for o in &p.toolpath.operations {
            eprintln!("  {}: {} {} moves", o.name, o.tool.spec(), o.moves.len());
        }
        let text = program_text(&p.toolpath, &opts).unwrap();
        let canon = read_back(&text, &opts).unwrap();
        let area = Area::from_paths(std::slice::from_ref(&p.contour));
        let (d, inside) = match p.part {
            Part::Insert => (-GOUGE_TOL, false),
            Part::Cavity => (GOUGE_TOL, true),
        };
        let rings = offset_areas(&area, d, 0.001)
            .unwrap()
            .iter()
            .flat_map(|a| {
                a.paths()
                    .map(|q| to_ring(&q.flatten(1e-4)))
                    .collect::<Vec<_>>()
            })
            .collect();
        let tools = p.toolpath.tools();
        let mut designs = vec![Design {
            rings,
            cut_inside: inside,
            top: 0.0,
            floor: -p.depth,
            slope: 0.0,
        }];
        // The seed's tools: 16 mm everywhere; on the insert the 6 mm mill and the 1 mm bit
        // in the tread (the slots are narrower than 6 mm: only the 1 mm bit fits them).
        let specs: Vec<String> = p
            .toolpath
            .operations
            .iter()
            .map(|o| o.tool.spec())
            .collect();
        if p.part == Part::Insert {
            assert!(specs.contains(&"flat:6".to_string()), "{specs:?}");
            assert!(specs.contains(&"flat:1".to_string()), "{specs:?}");
            let slots = offset_areas(&Area::from_paths(&p.tread), GOUGE_TOL, 0.001).unwrap();
            designs.push(Design {
                rings: slots
                    .iter()
                    .flat_map(|a| {
                        a.paths()
                            .map(|q| to_ring(&q.flatten(1e-4)))
                            .collect::<Vec<_>>()
                    })
                    .collect(),
                cut_inside: true,
                top: 0.0,
                floor: -oficina_cam::ops::TREAD_DEPTH,
                slope: 0.0,
            });
        }
        let last = &p.toolpath.operations.last().unwrap().tool;
        let check = check_mill(&canon, &tools, &designs, 0.5, 20.0, 40.0, last).unwrap();
        eprintln!(
            "{}: {} lines, gouge {:.4} at {:?}, scallop mean {:.4}",
            p.name(),
            text.lines().count(),
            check.report.max_gouge,
            check.report.gouge_at,
            check.report.scallop_mean
        );
        let uncut = check
            .stock
            .z
            .iter()
            .zip(&check.design.z)
            .filter(|(s, d)| **s > **d + 0.01)
            .count();
        let lowered = check.design.z.iter().filter(|d| **d < -1.0).count();
        eprintln!(
            "  uncut pixels {uncut} of {} ({} in the design's cut region), leftover mean {:.4}",
            check.design.z.len(),
            lowered,
            check.report.leftover_mean
        );
        if let Ok(dir) = std::env::var("OFICINA_SOLE_PNG") {
            oficina_sim::render_png(
                &check.stock,
                &std::path::Path::new(&dir).join(format!("{}.png", p.name())),
            )
            .unwrap();
        }
        assert!(check.report.max_gouge < 1e-3, "{}", p.name());
        if p.part == Part::Insert {
            // Each slot (3 mm wide before grading) is cut to its floor along its middle by
            // the 1 mm bit: check the stock there.
            for t in &p.tread {
                let bb = t.bounding_box().unwrap();
                if bb.height() > 6.0 {
                    continue;
                }
                let y = bb.center().y;
                let row = ((y - check.origin[1]) / check.stock.pixel).round() as usize;
                let mut deep = 0;
                let mut n = 0;
                let mut x = bb.x0 + 1.0;
                while x < bb.x1 - 1.0 {
                    let col = ((x - check.origin[0]) / check.stock.pixel).round() as usize;
                    let z = check.stock.z[row * check.stock.width + col];
                    n += 1;
                    if (z + 2.0).abs() < 0.01 {
                        deep += 1;
                    }
                    x += check.stock.pixel;
                }
                assert!(
                    n > 20 && deep == n,
                    "{}: {deep} of {n} at the floor",
                    p.name()
                );
            }
        }
        if p.part == Part::Cavity {
            // Only wall pixels (the grid against exact arcs) may stand above the floor.
            assert!(
                uncut * 1000 < lowered,
                "{}: {uncut} of {lowered} uncut",
                p.name()
            );
        }
    }
}
