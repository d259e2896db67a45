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
