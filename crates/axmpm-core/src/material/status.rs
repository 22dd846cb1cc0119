//! Which keys of a material table are retired and which are experimental, checked by
//! [`super::build`] before the model reads its table. The scenario front end asks the engine
//! for the same messages (`axmpm._core.material_key_errors`), so the rule is written once.
//!
//! Experimental options (and one whole model) were measured against the granular column
//! collapse but not validated (docs/studies/granular-variants.md); a table uses them only with
//! `experimental = true`.

use super::Parameters;

/// Where the measurements behind the retired keys are kept (in the repository).
pub const RETIRED_RECORD: &str = "docs/studies/granular-variants.md";

/// Keys a model no longer has: (model, key). A table that still sets one is refused with a
/// message naming it, rather than told the key is unknown.
pub const RETIRED: &[(&str, &str)] = &[
    ("mohr_coulomb", "recompaction"),
    ("mohr_coulomb", "cell_averaged_disconnection"),
    ("mohr_coulomb", "inertial_friction_angle"),
];

/// The key that opts a material table into its experimental options.
pub const EXPERIMENTAL_KEY: &str = "experimental";

/// Options accepted only with `experimental = true`: (model, key), the key `model` standing
/// for the whole model.
pub const EXPERIMENTAL: &[(&str, &str)] = &[
    ("granular_fluidity", "model"),
    ("drucker_prager", "inertial_friction"),
    ("drucker_prager", "critical_packing_fraction"),
    ("mohr_coulomb", "critical_packing_fraction"),
];

/// Why the experimental options are not in production.
const EXPERIMENTAL_REASON: &str = "measured, not validated";

/// Every problem of the table of a `model` material with its retired and experimental keys,
/// as (key, message). Absent keys and JSON `null` count as not given.
pub fn key_errors(p: &Parameters, model: &str) -> Vec<(String, String)> {
    let mut errors: Vec<(String, String)> = RETIRED
        .iter()
        .filter(|(m, key)| *m == model && p.is_given(key))
        .map(|(_, key)| (key.to_string(), format!("is not a {model} parameter (retired; see {RETIRED_RECORD})")))
        .collect();
    let opted_in = match p.bool_or(EXPERIMENTAL_KEY, false) {
        Ok(on) => on,
        Err(message) => {
            let message = message.split_once(": ").map_or(message.clone(), |(_, m)| m.to_string());
            errors.push((EXPERIMENTAL_KEY.to_string(), message));
            return errors;
        }
    };
    if !opted_in {
        let name = p.name();
        for (_, key) in EXPERIMENTAL.iter().filter(|(m, key)| *m == model && (*key == "model" || p.is_given(key))) {
            let what = if *key == "model" { format!("{model} is") } else { "is".to_string() };
            errors.push((
                key.to_string(),
                format!("{what} experimental ({EXPERIMENTAL_REASON}): set {EXPERIMENTAL_KEY} = true in [materials.{name}] to use it"),
            ));
        }
    }
    errors
}

/// [`key_errors`] as the first error, `materials.NAME.KEY: message`.
pub fn check(p: &Parameters, model: &str) -> Result<(), String> {
    match key_errors(p, model).into_iter().next() {
        Some((key, message)) => Err(p.error(&key, message)),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn a_retired_key_is_refused_by_name_and_null_counts_as_absent() {
        let table = json!({"friction_angle": 30.0, "recompaction": false, "inertial_friction_angle": null});
        let p = Parameters::new("sand", table.as_object().unwrap());
        assert_eq!(
            check(&p, "mohr_coulomb"),
            Err("materials.sand.recompaction: is not a mohr_coulomb parameter (retired; see docs/studies/granular-variants.md)"
                .to_string())
        );
        // The same key is no business of another model's (it is refused there as unknown by
        // the front end, and ignored by the engine).
        assert_eq!(check(&p, "drucker_prager"), Ok(()));
        let table = json!({"friction_angle": 30.0, "inertial_friction_angle": null});
        assert_eq!(check(&Parameters::new("sand", table.as_object().unwrap()), "mohr_coulomb"), Ok(()));
    }

    #[test]
    fn an_experimental_option_needs_the_opt_in_and_says_why() {
        let table = json!({"friction": 0.4, "inertial_friction": 0.6, "critical_packing_fraction": null});
        let p = Parameters::new("sand", table.as_object().unwrap());
        assert_eq!(
            check(&p, "drucker_prager"),
            Err("materials.sand.inertial_friction: is experimental (measured, not validated): set experimental = true in \
                 [materials.sand] to use it"
                .to_string())
        );
        let table = json!({"friction": 0.4, "inertial_friction": 0.6, "experimental": true});
        assert_eq!(check(&Parameters::new("sand", table.as_object().unwrap()), "drucker_prager"), Ok(()));
        let table = json!({"friction": 0.4, "experimental": false});
        assert_eq!(check(&Parameters::new("sand", table.as_object().unwrap()), "drucker_prager"), Ok(()));
        // The whole model, named by `model`.
        let table = json!({"static_friction": 0.38});
        assert_eq!(
            key_errors(&Parameters::new("sand", table.as_object().unwrap()), "granular_fluidity"),
            [("model".to_string(),
              "granular_fluidity is experimental (measured, not validated): set experimental = true in [materials.sand] \
               to use it".to_string())]
        );
        let table = json!({"critical_packing_fraction": 0.55, "experimental": "yes"});
        assert_eq!(
            check(&Parameters::new("sand", table.as_object().unwrap()), "mohr_coulomb"),
            Err("materials.sand.experimental: must be true or false (got \"yes\")".to_string())
        );
    }

    #[test]
    fn every_experimental_option_is_reported_without_the_opt_in() {
        for model in ["granular_fluidity", "drucker_prager", "mohr_coulomb", "linear_elastic"] {
            let table: serde_json::Map<_, _> =
                EXPERIMENTAL.iter().map(|(_, key)| (key.to_string(), json!(1.0))).collect();
            let errors = key_errors(&Parameters::new("sand", &table), model);
            let keys: Vec<&str> = errors.iter().map(|(k, _)| k.as_str()).collect();
            let want: Vec<&str> = EXPERIMENTAL.iter().filter(|(m, _)| *m == model).map(|(_, k)| *k).collect();
            assert_eq!(keys, want, "{model}");
        }
    }

    #[test]
    fn every_retired_key_is_reported() {
        let table: serde_json::Map<_, _> = RETIRED.iter().map(|(_, key)| (key.to_string(), json!(1.0))).collect();
        let errors = key_errors(&Parameters::new("sand", &table), "mohr_coulomb");
        let keys: Vec<&str> = errors.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(keys, RETIRED.iter().map(|(_, k)| *k).collect::<Vec<_>>());
    }
}
