//! Unit tests of the parameter table, its checks and its lookups.
use super::*;

#[test]
fn defaults_are_valid_and_match_specs() {
    let p = Params::default();
    p.validate().unwrap();
    for s in SPECS {
        let got = p.get(s.name).unwrap();
        assert!(
            got == s.default || (got.is_nan() && s.default.is_nan()),
            "{}",
            s.name
        );
    }
    assert_eq!(SPECS.len(), 46);
    assert_eq!(ParamId::ALL.len(), SPECS.len());
}

#[test]
fn ids_index_their_own_field_and_name() {
    // Index and name must agree field by field: give every field a distinct value through
    // the struct literal's order (SPECS order) and read it back by id and by name.
    let mut p = Params::default();
    for (k, &id) in ParamId::ALL.iter().enumerate() {
        p[id] = k as f64 + 0.5;
    }
    for (k, &id) in ParamId::ALL.iter().enumerate() {
        assert_eq!(id.spec().name, SPECS[k].name);
        assert_eq!(id.name().parse::<ParamId>(), Ok(id));
        assert_eq!(p.get(id.name()), Some(k as f64 + 0.5), "{id}");
        assert_eq!(p.pairs()[k], (id.name(), k as f64 + 0.5));
    }
    assert_eq!(p.speed_kmh, 0.5);
    assert_eq!(p.n_driven, 26.5);
    assert_eq!(p.speed_spread_kmh, 35.5);
    assert_eq!(p[ParamId::GMod], p.g_mod);
}

#[test]
fn operating_axes_are_the_operating_point_group() {
    let group: Vec<ParamId> = ParamId::ALL
        .iter()
        .copied()
        .filter(|id| id.spec().group == Group::OperatingPoint)
        .collect();
    assert_eq!(group, OPERATING_AXES);
    assert!(OPERATING_AXES.iter().all(|a| a.is_operating_axis()));
}

#[test]
fn unknown_name_lists_the_accepted_and_the_closest() {
    let e = "sped_kmh".parse::<ParamId>().unwrap_err();
    assert_eq!(
        e,
        ParamError::Unknown {
            name: "sped_kmh".into()
        }
    );
    assert!(e.to_string().contains("did you mean `speed_kmh`?"));
    assert!(
        e.to_string().ends_with(
            "carcass_share, belt_mass_share, toe_front_deg, toe_rear_deg, load_front_n, load_rear_n, pressure_front_kpa, pressure_rear_kpa"
        ),
        "{e}"
    );
}

#[test]
fn set_rejects_unknown_and_out_of_range() {
    let mut p = Params::default();
    assert!(matches!(
        p.set("nope", 1.0),
        Err(ParamError::Unknown { .. })
    ));
    let e = p.set("sped_kmh", 1.0).unwrap_err().to_string();
    assert!(
        e.starts_with(
            "unknown parameter `sped_kmh`; did you mean `speed_kmh`? accepted: speed_kmh, toe_deg"
        ),
        "{e}"
    );
    let e = p.set("toe_deg", 0.0).unwrap_err().to_string();
    assert!(e.contains("toe_deg") && e.contains("(0, 10]"), "{e}");
    assert!(p.set("load_n", f64::NAN).is_err());
    assert!(p.set("n_wheels", 2.5).is_err());
    p.set("load_n", 5000.0).unwrap();
    assert_eq!(p.load_n, 5000.0);
}

#[test]
fn cross_field_rules() {
    let p = Params {
        mu_s: 0.9,
        ..Params::default()
    };
    assert!(p.validate().unwrap_err().to_string().contains("mu_s"));
    let p = Params {
        n_driven: 6.0,
        ..Params::default()
    };
    assert!(p.validate().unwrap_err().to_string().contains("n_driven"));
    let p = Params {
        visible_depth_mm: 2.0,
        ..Params::default()
    };
    let e = p.validate().unwrap_err().to_string();
    assert!(
        e.contains("visible_depth_mm") && e.contains("limit_depth_mm"),
        "{e}"
    );
    let p = Params {
        visible_depth_mm: 1.5,
        ..Params::default()
    };
    p.validate().unwrap();
    // The usable depth is part of the tread, and the tire is worn out before it is gone.
    let p = Params {
        tread_depth_new_mm: 16.0,
        ..Params::default()
    };
    let e = p.validate().unwrap_err().to_string();
    assert!(
        e.contains("`tread_depth_new_mm` = 16 mm")
            && e.contains("(0, 15] mm")
            && e.contains("`tread_height` = 0.015 m"),
        "{e}"
    );
    Params {
        tread_depth_new_mm: 15.0,
        ..Params::default()
    }
    .validate()
    .unwrap();
    Params {
        tread_height: 0.008,
        ..Params::default()
    }
    .validate()
    .unwrap();
    for worn_out in [8.0, 9.0] {
        let p = Params {
            tread_depth_worn_out_mm: worn_out,
            ..Params::default()
        };
        let e = p.validate().unwrap_err().to_string();
        assert!(
            e.contains("`tread_depth_worn_out_mm`")
                && e.contains("[0, 8) mm")
                && e.contains("`tread_depth_new_mm` = 8 mm"),
            "{e}"
        );
    }
    let e = Params::default()
        .set("tread_depth_new_mm", 0.0)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("tread_depth_new_mm") && e.contains("(0, 200]"),
        "{e}"
    );
    assert!((Params::default().usable_wear_m() - 6.4e-3).abs() < 1e-15);
}
