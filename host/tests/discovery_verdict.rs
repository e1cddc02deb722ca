//! What the verdict carries in the JSON: one score type for candidates and
//! located laws, and the equivalent readings of each located law
//! (src/workbench/{verdict,stagewise_verdict}.rs).

use crate::fixtures::diagnosed::swimbot_cmd;

/// A catalogue candidate and a located law carry one
/// score type, flattened, so the JSON keeps the six fields at the top of
/// each entry (no nested `score`) and they read alike in both lists.
#[test]
fn candidates_and_located_laws_carry_the_same_score_fields_in_the_json() {
    let dir = tempfile::tempdir().unwrap();
    let out = swimbot_cmd(&["diagnose", "--format", "json"], dir.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let ranking = json["ranking"].as_array().unwrap();
    let located = json["discovery"]["located"].as_array().unwrap();
    assert!(!ranking.is_empty() && !located.is_empty());
    for entry in ranking.iter().chain(located) {
        let obj = entry.as_object().unwrap();
        assert!(!obj.contains_key("score"), "{entry}");
        for key in ["mare", "cv_mare", "chi2"] {
            assert!(
                obj[key].as_f64().is_some_and(f64::is_finite),
                "{key}: {entry}"
            );
        }
        for key in ["chi2_reduced", "aicc"] {
            assert!(obj[key].is_number() || obj[key].is_null(), "{key}: {entry}");
        }
        assert!(obj["at_noise_floor"].is_boolean(), "{entry}");
    }
    // Every located law states its equivalent readings.
    for l in located {
        let eq = l["equivalent"].as_array().unwrap();
        if l["place"] == "tail.torque" {
            assert_eq!(eq[0]["place"], "body.E_x", "{l}");
            assert_eq!(eq[0]["relation"], "reciprocal", "{l}");
        }
    }
    // The paper's data are above the floor for the base model: a located
    // law's chi-square is below the baseline's, as its score says.
    let base_chi2 = json["baseline"]["chi2"].as_f64().unwrap();
    assert!(located[0]["chi2"].as_f64().unwrap() < base_chi2);
    // The set of steps carries its joint reading; each parameter names a
    // step of `verdict.steps` (from 1).
    let steps = json["verdict"]["steps"].as_array().unwrap();
    let joint = &json["verdict"]["joint"];
    assert!(steps.len() >= 2, "{}", json["verdict"]);
    for key in ["traded", "shared_places", "no_effect_within"] {
        assert!(joint[key].is_array(), "{key}: {joint}");
    }
    for t in joint["traded"].as_array().unwrap() {
        for p in t["params"].as_array().unwrap() {
            let step = p["step"].as_u64().unwrap() as usize;
            assert!((1..=steps.len()).contains(&step), "{t}");
        }
    }
}
