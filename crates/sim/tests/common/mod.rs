//! What the sim crate's test binaries share.
// Each test binary compiles this module and uses part of it.
#![allow(dead_code)]

use oficina_cam::relief::Planned;
use oficina_io::Heightmap;
use oficina_sim::replay;

/// The planned toolpath's canonical operations replayed on fresh flat stock (top at 0) from
/// (0, 0, 5): the tests' own simulation, independent of the CAM's stock and of the carve
/// pipeline (which replays the interpreted program text instead).
pub(crate) fn replay_on_fresh_stock(design: &Heightmap, planned: &Planned) -> Heightmap {
    let tools = planned.toolpath.tools();
    let mut stock = Heightmap::flat(design.width, design.height, design.pixel, 0.0);
    replay(
        planned.toolpath.canon(),
        &tools,
        &mut stock,
        [0.0, 0.0, 5.0],
    )
    .unwrap();
    stock
}
