//! Programs and images bundled in the binary, so the page opens with something to run.

pub(crate) const PROGRAMS: &[(&str, &str)] = &[
    (
        "plate.nc",
        include_str!("../../../samples/workbench/plate.nc"),
    ),
    (
        "router-square.nc",
        include_str!("../../../samples/motion/router-square.nc"),
    ),
    (
        "polar-shapes.nc",
        include_str!("../../../samples/motion/polar-shapes.nc"),
    ),
];

pub(crate) const IMAGES: &[(&str, &[u8])] = &[(
    "dome.png",
    include_bytes!("../../../samples/relief/dome.png"),
)];

/// The program the page opens with when none is given.
pub(crate) const DEFAULT: &str = "plate.nc";

/// Designs for the processes: a drawing to mill, a contour for sole molds, a drawing to plot, a design to embroider.
pub(crate) const DESIGNS: &[(&str, &str)] = &[
    ("plate.svg", include_str!("../../../samples/mill/plate.svg")),
    ("holes.svg", include_str!("../../../samples/mill/holes.svg")),
    (
        "size34.csv",
        include_str!("../../../samples/sole/size34.csv"),
    ),
    (
        "design.svg",
        include_str!("../../../samples/plot/design.svg"),
    ),
    ("house.plt", include_str!("../../../samples/plot/house.plt")),
    (
        "sunflower.svg",
        include_str!("../../../samples/embroidery/sunflower.svg"),
    ),
];
