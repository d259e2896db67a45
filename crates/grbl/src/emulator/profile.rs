//! grbl settings from an Oficina machine profile, so the emulator behaves like the machine
//! the rest of Oficina plans for: steps/mm ($100…), maximum rates ($110…, mm/min),
//! accelerations ($120…), travel ($130…), junction deviation ($11) and arc tolerance ($12).

use oficina_motion::profile::KinematicsKind;
use oficina_motion::Profile;

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
    Ok(out)
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
}
