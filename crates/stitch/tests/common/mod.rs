//! What the stitch crate's test binaries share: the repository's sample design.
// Each test binary compiles this module and uses part of it.
#![allow(dead_code)]

use oficina_stitch::{generate, Generated, Params, StitchPlan};

/// The sample design (`samples/embroidery/sunflower.svg`, through Oficina's importer)
/// generated as `name` with `params`.
pub(crate) fn sunflower(name: &str, params: &Params) -> Generated {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../samples/embroidery/sunflower.svg");
    let imported = oficina_io::load_drawing(&path).unwrap();
    generate(&imported.drawing, name, params, &mut |_, _| {}).unwrap()
}

/// The sample design's plan with the default parameters.
pub(crate) fn sample() -> StitchPlan {
    sunflower("sunflower", &Params::default()).plan
}

/// An Ink/Stitch SVG text sewn as `oficina embroider` sews it: read its parameters, strip the
/// commands' symbols, import (text not drawn), generate with `params`.
pub(crate) fn sew_inkstitch(svg: &str, params: &Params) -> StitchPlan {
    let ink = oficina_stitch::read_inkstitch(svg, "t.svg").unwrap();
    let text = ink.strip(svg);
    let no_text = oficina_io::SvgOptions { draw_text: false };
    let d = oficina_io::read_svg(text.as_bytes(), "t.svg", &no_text)
        .unwrap()
        .drawing;
    oficina_stitch::generate_inkstitch(&d, "t", params, &ink, &mut |_, _| {})
        .unwrap()
        .plan
}

/// The plan's sewn needle points (x, y), in order.
pub(crate) fn sewn(plan: &StitchPlan) -> Vec<(f64, f64)> {
    plan.entries()
        .filter(|(_, s)| s.kind == oficina_stitch::Kind::Stitch)
        .map(|(_, s)| (s.x, s.y))
        .collect()
}
