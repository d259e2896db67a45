//! `oficina emulate grbl`'s probe options: what the emulated probe input touches (a stock
//! block with a tilted, warped top, a touch plate on it, a tool length setter) and the tool
//! in the spindle, read into the emulator's [`ProbeModel`] and checked by it.

use anyhow::{bail, Context};
use oficina_grbl_emu::{LengthSetter, ProbeModel, Stock, Tool, TouchPlate};

/// Probe options (machine coordinates, mm).
#[derive(clap::Args, Debug)]
pub(crate) struct ProbeArgs {
    /// A stock block the probe touches (its top and, below the top, its sides):
    /// corners X0,Y0 and X1,Y1 and the top's machine Z, e.g. 10,20,210,170,-60.
    #[arg(long, value_name = "X0,Y0,X1,Y1,ZTOP", allow_hyphen_values = true)]
    pub probe_block: Option<String>,
    /// A touch plate lying on the block: corners and thickness, e.g. 100,60,140,100,10.
    #[arg(
        long,
        value_name = "X0,Y0,X1,Y1,THICK",
        allow_hyphen_values = true,
        requires = "probe_block"
    )]
    pub probe_plate: Option<String>,
    /// A tool length setter (a 10 mm pad): its centre and its top's machine Z.
    #[arg(long, value_name = "X,Y,ZTOP", allow_hyphen_values = true)]
    pub probe_setter: Option<String>,
    /// Tilt of the block's top: mm of Z per mm of X and per mm of Y (the top is
    /// ZTOP + AX·x + AY·y).
    #[arg(
        long,
        value_name = "AX,AY",
        allow_hyphen_values = true,
        requires = "probe_block"
    )]
    pub probe_tilt: Option<String>,
    /// Warp of the block's top, W·sin(2πx/λ)·sin(2πy/λ): amplitude and wavelength, mm.
    #[arg(
        long,
        value_name = "W,LAMBDA",
        allow_hyphen_values = true,
        requires = "probe_block"
    )]
    pub probe_warp: Option<String>,
    /// Length of the tool in the spindle: its tip is this far below the machine Z.
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "MM",
        allow_hyphen_values = true
    )]
    pub tool_length: f64,
    /// Diameter of the tool in the spindle (its side touches the block's sides).
    #[arg(long, default_value_t = 0.0, value_name = "MM")]
    pub tool_diameter: f64,
}

/// The emulator's probe model from the options, refused with the option named when it
/// cannot be.
pub(crate) fn model(a: &ProbeArgs) -> anyhow::Result<ProbeModel> {
    let mut stock = match &a.probe_block {
        Some(s) => {
            let [x0, y0, x1, y1, top] = numbers("--probe-block", s)?;
            Some(Stock::flat([x0, y0], [x1, y1], top))
        }
        None => None,
    };
    if let (Some(st), Some(t)) = (stock.as_mut(), &a.probe_tilt) {
        st.tilt = numbers("--probe-tilt", t)?;
    }
    if let (Some(st), Some(w)) = (stock.as_mut(), &a.probe_warp) {
        [st.warp, st.wavelength] = numbers("--probe-warp", w)?;
    }
    let plate = match &a.probe_plate {
        Some(s) => {
            let [x0, y0, x1, y1, thickness] = numbers("--probe-plate", s)?;
            Some(TouchPlate {
                min: [x0, y0],
                max: [x1, y1],
                thickness,
            })
        }
        None => None,
    };
    let setter = match &a.probe_setter {
        Some(s) => {
            let [x, y, top] = numbers("--probe-setter", s)?;
            Some(LengthSetter { at: [x, y], top })
        }
        None => None,
    };
    let model = ProbeModel {
        stock,
        plate,
        setter,
        tool: Tool {
            length: a.tool_length,
            diameter: a.tool_diameter,
        },
    };
    model
        .check()
        .map_err(|e| anyhow::anyhow!("probe options: {e}"))?;
    Ok(model)
}

/// Exactly `N` comma-separated numbers.
fn numbers<const N: usize>(option: &str, s: &str) -> anyhow::Result<[f64; N]> {
    let v = s
        .split(',')
        .map(|x| {
            x.trim()
                .parse::<f64>()
                .with_context(|| format!("{option} {s}: '{}' is not a number", x.trim()))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    match <[f64; N]>::try_from(v) {
        Ok(a) => Ok(a),
        Err(v) => bail!(
            "{option} {s}: expected {N} numbers separated by commas, got {}",
            v.len()
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args() -> ProbeArgs {
        ProbeArgs {
            probe_block: Some("10,20,210,170,-60".into()),
            probe_plate: Some("100,60,140,100,10".into()),
            probe_setter: None,
            probe_tilt: Some("0.001,-0.002".into()),
            probe_warp: Some("0.2,50".into()),
            tool_length: 0.0,
            tool_diameter: 6.0,
        }
    }

    #[test]
    fn options_become_the_model_and_bad_ones_are_named() {
        let m = model(&args()).unwrap();
        let s = m.stock.unwrap();
        assert_eq!((s.min, s.max, s.top), ([10.0, 20.0], [210.0, 170.0], -60.0));
        assert_eq!((s.tilt, s.warp, s.wavelength), ([0.001, -0.002], 0.2, 50.0));
        assert_eq!(m.plate.unwrap().thickness, 10.0);
        let bad = |f: fn(&mut ProbeArgs)| {
            let mut a = args();
            f(&mut a);
            model(&a).unwrap_err().to_string()
        };
        assert!(bad(|a| a.probe_block = Some("1,2,3".into())).contains("expected 5 numbers"));
        assert!(bad(|a| a.probe_plate = Some("1,2,3,4,x".into())).contains("'x' is not a number"));
        assert!(bad(|a| a.probe_plate = Some("100,60,140,100,-1".into())).contains("negative"));
        assert!(bad(|a| a.probe_block = Some("10,20,0,170,-60".into())).contains("first corner"));
        assert!(bad(|a| a.tool_diameter = -1.0).contains("diameter"));
    }
}
