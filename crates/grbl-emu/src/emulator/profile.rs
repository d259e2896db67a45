//! grbl settings from an Oficina machine profile, so the emulator behaves like the machine
//! the rest of Oficina plans for: steps/mm ($100…), maximum rates ($110…, mm/min),
//! accelerations ($120…), travel ($130…), junction deviation ($11) and arc tolerance ($12);
//! and back: the motion profile the emulator plans with, from its `$` settings.

use oficina_motion::Profile;
use oficina_motion::{Joint, KinematicsKind, Rotary, VelocityProfile};
use std::collections::BTreeMap;

/// grbl 1.1's step rate ceiling on a 16 MHz ATmega328P (its documented 30 kHz).
pub const GRBL_MAX_STEP_RATE: f64 = 30_000.0;

/// The `$N` values a grbl board for `profile` would carry. Only Cartesian machines have a
/// stock grbl build.
pub fn grbl_settings(profile: &Profile) -> Result<Vec<(u16, f64)>, String> {
    if profile.kinematics != KinematicsKind::Cartesian {
        return Err(format!(
            "profile '{}' is not Cartesian; stock grbl drives Cartesian machines only",
            profile.name
        ));
    }
    let mut out = vec![
        (11, profile.junction_deviation),
        (12, profile.arc_tolerance),
    ];
    for (i, joint) in profile.joints.iter().enumerate() {
        let Some(j) = joint else {
            return Err(format!(
                "profile '{}' has no {} joint; grbl needs X, Y and Z",
                profile.name,
                ["X", "Y", "Z"][i]
            ));
        };
        let i = i as u16;
        out.push((100 + i, j.steps_per_unit));
        // The profile keeps mm/s internally; grbl's $110 is mm/min.
        out.push((110 + i, j.max_rate * 60.0));
        out.push((120 + i, j.acceleration));
        let t = profile.travel[i as usize];
        out.push((130 + i, t[1] - t[0]));
    }
    // A 4th axis A as grblHAL numbers it (N_AXIS = 4): $103 steps/°, $113 °/min, $123 °/s²,
    // $133 travel (°; 0 for a chuck that turns without end).
    if let Some(a) = &profile.rotary[0] {
        let j = &a.joint;
        let travel = match (a.wrap, j.limits) {
            (false, Some([lo, hi])) => hi - lo,
            _ => 0.0,
        };
        out.extend([
            (103, j.steps_per_unit),
            (113, j.max_rate * 60.0),
            (123, j.acceleration),
            (133, travel),
        ]);
    }
    Ok(out)
}

/// The Cartesian machine a grbl board with these `$` settings drives (values missing from
/// `settings` count as 0). Zero or negative rates and accelerations, which grbl accepts but
/// cannot move with, are raised to a crawl so the emulator never divides by zero.
pub fn motion_profile(settings: &BTreeMap<u16, f64>) -> Profile {
    let get = |n: u16| settings.get(&n).copied().unwrap_or(0.0);
    let names = KinematicsKind::Cartesian.joint_names();
    let joint = |i: u16| Joint {
        name: names.get(i as usize).copied().unwrap_or("a"),
        steps_per_unit: get(100 + i).max(1e-3),
        // $110 is mm/min; the profile keeps mm/s.
        max_rate: get(110 + i).max(1.0) / 60.0,
        acceleration: get(120 + i).max(0.1),
        jerk: None,
        backlash: 0.0,
        invert_direction: false,
        limits: None,
        homing: None,
    };
    Profile {
        name: "grbl $ settings".into(),
        kinematics: KinematicsKind::Cartesian,
        joints: [Some(joint(0)), Some(joint(1)), Some(joint(2))],
        // $103…$133 set: a 4th axis A that turns without end unless $133 bounds it.
        rotary: [
            settings.contains_key(&103).then(|| Rotary {
                joint: joint(3),
                wrap: get(133) <= 0.0,
            }),
            None,
            None,
        ],
        // grbl's machine space with soft limits: [-$13x, 0].
        travel: [0, 1, 2].map(|i| [-get(130 + i), 0.0]),
        start: [0.0; 3],
        junction_deviation: get(11).max(0.0),
        arc_tolerance: get(12).max(1e-4),
        path_tolerance: get(12).max(1e-4),
        shape: VelocityProfile::Trapezoid,
        horizon: f64::INFINITY,
        max_step_rate: GRBL_MAX_STEP_RATE,
        default_feed: 1.0,
        work_offset: [0.0; 3],
        tool_table: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn router_profile_becomes_grbl_settings() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../profiles/grbl-router.toml"
        );
        let p = Profile::load(std::path::Path::new(path)).unwrap();
        let s: std::collections::BTreeMap<u16, f64> =
            grbl_settings(&p).unwrap().into_iter().collect();
        // The values written in the profile file, in grbl's units.
        assert_eq!(s[&100], 200.0);
        assert!((s[&110] - 6000.0).abs() < 1e-9);
        assert!((s[&112] - 1500.0).abs() < 1e-9);
        assert_eq!(s[&120], 300.0);
        assert_eq!(s[&130], 800.0);
        assert_eq!(s[&132], 100.0);
        assert_eq!(s[&11], 0.01);
    }

    #[test]
    fn settings_become_a_motion_profile_and_back() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../profiles/grbl-router.toml"
        );
        let p = Profile::load(std::path::Path::new(path)).unwrap();
        let s: BTreeMap<u16, f64> = grbl_settings(&p).unwrap().into_iter().collect();
        let back = motion_profile(&s);
        for i in 0..3 {
            let (a, b) = (p.joints[i].unwrap(), back.joints[i].unwrap());
            assert!((a.max_rate - b.max_rate).abs() < 1e-12);
            assert_eq!(a.acceleration, b.acceleration);
            assert_eq!(a.steps_per_unit, b.steps_per_unit);
        }
        assert_eq!(back.junction_deviation, p.junction_deviation);
        // Nonsense settings still give a machine that moves.
        let zero = motion_profile(&BTreeMap::new());
        assert!(zero.joints[0].unwrap().max_rate > 0.0);
        assert!(zero.joints[0].unwrap().acceleration > 0.0);
    }
}
