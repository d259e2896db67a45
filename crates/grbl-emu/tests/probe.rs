//! The probe routines of `oficina-grbl` against the emulator's probe, on each firmware
//! flavour, over TCP as a sender meets a board. Every expectation is computed here from the
//! model's numbers (block, plate, setter, tool), not from the emulator's code.

use oficina_grbl::{
    run_corner, run_tool_setter, run_z_plate, Approach, Corner, Endpoint, ProbeError, Response,
    Sender, SenderOptions, ToolSetter, ZPlate,
};
use oficina_grbl_emu::{
    Config, Emulator, Flavor, LengthSetter, ProbeModel, Stock, Tool, TouchPlate,
};

const FLAVORS: [Flavor; 3] = [Flavor::Grbl, Flavor::GrblHal, Flavor::FluidNc];

/// The stock block: X 10…210, Y 20…170, its top at machine Z −60.
const STOCK_MIN: [f64; 2] = [10.0, 20.0];
const STOCK_TOP: f64 = -60.0;
/// The plate: 10 mm thick, X 100…140, Y 60…100.
const PLATE: f64 = 10.0;
/// The setter's pad top at Z −80, centred at X 250 Y 50.
const SETTER_AT: [f64; 2] = [250.0, 50.0];
const SETTER_TOP: f64 = -80.0;

fn model() -> ProbeModel {
    ProbeModel {
        stock: Some(Stock::flat(STOCK_MIN, [210.0, 170.0], STOCK_TOP)),
        plate: Some(TouchPlate {
            min: [100.0, 60.0],
            max: [140.0, 100.0],
            thickness: PLATE,
        }),
        setter: Some(LengthSetter {
            at: SETTER_AT,
            top: SETTER_TOP,
        }),
        tool: Tool::default(),
    }
}

fn start(flavor: Flavor) -> (Emulator, Sender) {
    let base = Config::flavored(flavor);
    let mut settings = base.settings.clone();
    // Fast axes; $10=0 so `?` reports the work position (WPos) itself.
    settings.extend([
        (110, 60000.0),
        (111, 60000.0),
        (112, 60000.0),
        (120, 20000.0),
        (121, 20000.0),
        (122, 20000.0),
        (10, 0.0),
    ]);
    let emu = Emulator::start(Config {
        baud: None,
        settings,
        probe: model(),
        ..base
    });
    let addr = emu.serve_tcp("127.0.0.1:0").unwrap();
    let sender = Sender::connect(
        &Endpoint::Tcp {
            addr: addr.to_string(),
        },
        SenderOptions::default(),
    )
    .unwrap();
    (emu, sender)
}

/// Quick touches, so each routine takes a couple of seconds.
fn quick() -> Approach {
    Approach {
        travel: 30.0,
        feed: 3000.0,
        slow_feed: 300.0,
        retract: 2.0,
    }
}

fn send(s: &mut Sender, line: &str) -> Vec<String> {
    let r = s.command(line).unwrap();
    assert_eq!(r.error, None, "{line}: {:?}", r.lines);
    r.lines
}

/// The `[TAG:x,y,z…]` of `$#`.
fn parameter(s: &mut Sender, tag: &str) -> Vec<f64> {
    send(s, "$#")
        .iter()
        .find_map(|l| match Response::parse(l) {
            Response::Feedback { tag: t, value } if t == tag => Some(
                value
                    .split([',', ':'])
                    .map(|v| v.parse().unwrap())
                    .collect(),
            ),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no [{tag}:…] in $#"))
}

fn work_pos(s: &mut Sender) -> Vec<f64> {
    send(s, "G4 P0");
    s.status().unwrap().wpos.expect("WPos with $10=0")
}

fn near(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b} (±{tol})");
}

#[test]
fn z_plate_puts_the_stock_top_at_z0_on_every_flavor() {
    for flavor in FLAVORS {
        let (_emu, mut s) = start(flavor);
        send(&mut s, "G90 G0 X120 Y80 Z-40");
        let p = ZPlate {
            thickness: PLATE,
            wcs: 2,
            approach: quick(),
        };
        let r = run_z_plate(&mut s, &p).unwrap();
        let plate_top = STOCK_TOP + PLATE;
        near(r.contacts[0][2], plate_top, 0.001, "contact");
        assert_eq!(r.wcs, 2);
        // G55's Z is the stock top's machine Z: work Z0 there.
        near(r.offset[2], STOCK_TOP, 0.002, "offset");
        near(parameter(&mut s, "G55")[2], STOCK_TOP, 0.002, "$# G55");
        assert_eq!(parameter(&mut s, "PRB")[3], 1.0, "{flavor}: $# PRB touched");
        // Left `retract` above the plate; then beside it, down onto the stock: Z0.
        send(&mut s, "G55");
        near(work_pos(&mut s)[2], PLATE + 2.0, 0.002, "above the plate");
        send(&mut s, "G0 X60 Y80");
        send(&mut s, "G38.2 Z-20 F3000");
        near(work_pos(&mut s)[2], 0.0, 0.002, "stock top in work Z");
        // The routine gave the units and distance mode back.
        let gc = send(&mut s, "$G").join(" ");
        assert!(gc.contains("G21") && gc.contains("G90"), "{flavor}: {gc}");
    }
}

#[test]
fn corner_finds_the_corner_with_the_tool_radius_on_every_flavor() {
    for flavor in FLAVORS {
        let (emu, mut s) = start(flavor);
        let diameter = 6.35;
        emu.set_tool(Tool {
            length: 0.0,
            diameter,
        });
        // Over the stock, 8 mm in from both sides, 5 mm above the top.
        send(&mut s, "G90 G0 X18 Y28 Z-55");
        let p = Corner {
            thickness: 0.0,
            side_offset: [0.0; 2],
            tool_diameter: diameter,
            reach: 15.0,
            depth: 3.0,
            wcs: 1,
            approach: quick(),
        };
        let r = run_corner(&mut s, &p).unwrap();
        // The side is touched with the axis one radius before it.
        near(
            r.contacts[1][0],
            STOCK_MIN[0] - diameter / 2.0,
            0.001,
            "X touch",
        );
        near(
            r.contacts[2][1],
            STOCK_MIN[1] - diameter / 2.0,
            0.001,
            "Y touch",
        );
        let g54 = parameter(&mut s, "G54");
        for (a, want) in [STOCK_MIN[0], STOCK_MIN[1], STOCK_TOP]
            .into_iter()
            .enumerate()
        {
            near(g54[a], want, 0.005, &format!("{flavor}: G54 axis {a}"));
            near(r.offset[a], want, 0.005, "offset");
        }
        // Back where it started: 8, 8 from the corner, 2 above the top.
        let w = work_pos(&mut s);
        for (a, want) in [8.0, 8.0, 2.0].into_iter().enumerate() {
            near(w[a], want, 0.005, &format!("{flavor}: WPos axis {a}"));
        }
    }
}

#[test]
fn corner_with_a_plate_on_top() {
    // The plate lies in the corner's region: the top is touched on it, the sides below it.
    let (emu, mut s) = start(Flavor::Grbl);
    emu.with_core(|c| {
        c.config.probe.plate = Some(TouchPlate {
            min: [14.0, 24.0],
            max: [40.0, 50.0],
            thickness: PLATE,
        })
    });
    send(&mut s, "G90 G0 X20 Y30 Z-45");
    let p = Corner {
        thickness: PLATE,
        side_offset: [0.0; 2],
        tool_diameter: 0.0,
        reach: 15.0,
        depth: PLATE + 3.0,
        wcs: 1,
        approach: quick(),
    };
    let r = run_corner(&mut s, &p).unwrap();
    near(r.contacts[0][2], STOCK_TOP + PLATE, 0.001, "plate top");
    for (a, want) in [STOCK_MIN[0], STOCK_MIN[1], STOCK_TOP]
        .into_iter()
        .enumerate()
    {
        near(r.offset[a], want, 0.005, &format!("G54 axis {a}"));
    }
}

#[test]
fn tool_setter_measures_and_a_longer_tool_gets_its_offset_on_every_flavor() {
    for flavor in FLAVORS {
        let (emu, mut s) = start(flavor);
        // Reference tool: the work is zeroed on the stock with it.
        send(&mut s, "G90 G0 X120 Y80 Z-40");
        let plate = ZPlate {
            thickness: PLATE,
            wcs: 1,
            approach: quick(),
        };
        run_z_plate(&mut s, &plate).unwrap();
        let setter = ToolSetter {
            at: Some(SETTER_AT),
            // Above the plate (−50) on the way; the pad is 35 mm below.
            safe_z: -45.0,
            reference: None,
            approach: Approach {
                travel: 40.0,
                ..quick()
            },
        };
        let first = run_tool_setter(&mut s, &setter).unwrap();
        near(first.measured_z, SETTER_TOP, 0.001, "reference tool");
        assert_eq!(first.tool_offset, None);
        // A tool 12.5 mm longer: it touches 12.5 higher; the offset is applied.
        let longer = 12.5;
        emu.set_tool(Tool {
            length: longer,
            diameter: 0.0,
        });
        let again = run_tool_setter(
            &mut s,
            &ToolSetter {
                reference: Some(first.measured_z),
                ..setter
            },
        )
        .unwrap();
        near(again.measured_z, SETTER_TOP + longer, 0.001, "longer tool");
        near(again.tool_offset.unwrap(), longer, 0.002, "offset");
        near(
            parameter(&mut s, "TLO")[0],
            longer,
            0.002,
            &format!("{flavor}: $# TLO"),
        );
        // With the offset, the longer tool's tip reads Z0 on the stock's top.
        send(&mut s, "G90 G0 Z20");
        send(&mut s, "G0 X60 Y80");
        send(&mut s, "G38.2 Z-10 F3000");
        near(
            work_pos(&mut s)[2],
            0.0,
            0.002,
            &format!("{flavor}: tip on the top"),
        );
    }
}

#[test]
fn failures_are_explained_and_g38_3_does_not_alarm() {
    for flavor in FLAVORS {
        let (_emu, mut s) = start(flavor);
        // No plate under the tool (beside the stock): ALARM:5, explained.
        send(&mut s, "G90 G0 X300 Y80 Z-40");
        let plate = ZPlate {
            thickness: PLATE,
            wcs: 1,
            approach: quick(),
        };
        let e = run_z_plate(&mut s, &plate).unwrap_err();
        assert!(matches!(e, ProbeError::NoContact(_)), "{flavor}: {e}");
        let text = e.to_string();
        assert!(
            text.contains("no contact") && text.contains("ALARM:5 (Probe fail"),
            "{text}"
        );
        assert_eq!(s.status().unwrap().state, oficina_grbl::GrblState::Alarm);
        // Nothing was set.
        assert_eq!(parameter(&mut s, "G54")[2], 0.0);
        send(&mut s, "$X");
        send(&mut s, "G90");
        // G38.3 over nothing: `[PRB:…:0]`, `ok`, no alarm.
        let lines = send(&mut s, "G91 G38.3 Z-5 F1000");
        assert!(
            lines
                .iter()
                .any(|l| l.starts_with("[PRB:") && l.ends_with(":0]")),
            "{lines:?}"
        );
        assert!(!lines.iter().any(|l| l.starts_with("ALARM")), "{lines:?}");
        assert_ne!(s.status().unwrap().state, oficina_grbl::GrblState::Alarm);
        // Resting on the stock: the probe is closed before the move, ALARM:4.
        send(&mut s, "G90 G0 X60 Y80");
        send(&mut s, "G0 Z-60");
        let e = run_z_plate(&mut s, &plate).unwrap_err();
        assert!(
            matches!(e, ProbeError::AlreadyTriggered(_)),
            "{flavor}: {e}"
        );
        assert!(e.to_string().contains("ALARM:4 (Probe fail"), "{e}");
    }
}

#[test]
fn a_machine_trait_object_runs_the_routine() {
    // The web server holds a `Box<dyn Machine>`: the routine runs through `raw_line`.
    use oficina_machine::Machine;
    let emu = Emulator::start(Config {
        baud: None,
        probe: model(),
        settings: vec![
            (110, 60000.0),
            (111, 60000.0),
            (112, 60000.0),
            (120, 2000.0),
            (121, 2000.0),
            (122, 2000.0),
        ],
        ..Config::default()
    });
    let addr = emu.serve_tcp("127.0.0.1:0").unwrap();
    let mut dev: Box<dyn Machine> =
        Box::new(oficina_grbl::GrblDevice::new(&format!("tcp://{addr}")).unwrap());
    dev.connect().unwrap();
    dev.raw_line("G90 G0 X120 Y80 Z-40").unwrap();
    let p = ZPlate {
        thickness: PLATE,
        wcs: 1,
        approach: quick(),
    };
    let r = run_z_plate(dev.as_mut(), &p).unwrap();
    near(
        r.offset[2],
        STOCK_TOP,
        0.002,
        "G54 Z through the Machine trait",
    );
    // The virtual machine has no firmware lines: refused in words, not a panic.
    let profile = oficina_motion::resolve("grbl-router").unwrap();
    let mut vm = oficina_machine::VirtualMachine::new(profile);
    let e = run_z_plate(&mut vm, &p).unwrap_err();
    assert!(e.to_string().contains("no firmware lines"), "{e}");
}

#[test]
fn a_tilted_warped_top_is_touched_where_the_formula_says() {
    // What an auto-levelling probe meets: z(x, y) = z0 + ax·x + ay·y + w·sin(2πx/λ)·sin(2πy/λ).
    let (z0, ax, ay, w, lambda) = (-60.0, 0.002, -0.001, 0.15, 37.0);
    let (emu, mut s) = start(Flavor::Grbl);
    emu.with_core(|c| {
        c.config.probe.plate = None;
        let st = c.config.probe.stock.as_mut().unwrap();
        st.tilt = [ax, ay];
        st.warp = w;
        st.wavelength = lambda;
    });
    let k = std::f64::consts::TAU / lambda;
    for (x, y) in [(30.0, 40.0), (77.7, 123.4), (205.0, 25.0)] {
        let want = z0 + ax * x + ay * y + w * (k * x).sin() * (k * y).sin();
        send(&mut s, &format!("G90 G0 X{x} Y{y} Z-50"));
        let lines = send(&mut s, "G38.2 Z-70 F3000");
        let prb = lines
            .iter()
            .find_map(|l| l.strip_prefix("[PRB:").and_then(|l| l.strip_suffix(":1]")))
            .unwrap_or_else(|| panic!("no contact at {x},{y}: {lines:?}"));
        let z: f64 = prb.split(',').nth(2).unwrap().parse().unwrap();
        // [PRB:…] has three decimals.
        near(z, want, 0.0006, &format!("top at {x},{y}"));
    }
}
