//! Scaffolding shared by the held-out batches of discovery
//! (docs/held-out.md, docs/held-out-2.md; the examples
//! `discovery_held_out` and `discovery_held_out_2` include it by
//! `#[path]`): a design's seeded draws, a truth made of fixture laws, the
//! frozen file's hash, and the scoring of a verdict against the places a
//! truth acts at.
//!
//! Scored from the verdict alone, each stated member read at every place
//! the verdict states as its equivalent (`discovery::interpret::
//! equivalents`; a catalogue effect as the place it acts at: `buoyancy`
//! as load.force, `body-correction` as body.D_x and body.E_x): **right**
//! (strict) is a `located` or `identified` verdict whose one set reads as
//! exactly the true places, or `none-needed` where the truth is
//! unobservable; **stated with rivals** an `indistinguishable` verdict
//! with the truth in a stated set; **wrong alone** a `located`/`identified`
//! set with a member that reads as no true place; **at the floor** the
//! found set (or the base) at the floor.

// Each example uses a part of this module; what one leaves unused is not
// dead in the other.
#![allow(dead_code)]

use nalgebra::Matrix6;
use rand::{rngs::StdRng, Rng, SeedableRng};
use sha2::{Digest, Sha256};
use swimbot::data::{Case, Dataset};
use swimbot::effects::place::Place;
use swimbot::effects::{Effect, EffectError};
use swimbot::model::Model;
use swimbot::physics::coefficients::LocalDrag;
use swimbot::physics::solve::ForceBalance;
use swimbot::workbench::diagnose::{Verdict, VerdictKind};
use swimbot::workbench::discovery::interpret::equivalents;
use swimbot::workbench::discovery::Table;

/// The seeded stream `salt` of a design: 1 draws the design, 2 the truth's
/// constants.
pub fn rng(seed: u64, salt: u64) -> StdRng {
    StdRng::seed_from_u64(seed.wrapping_mul(7_000_003).wrapping_add(salt))
}

/// `max(0, x/x0 - 1)^p`: zero below the threshold `x0`, growing past it.
pub fn onset(x: f64, x0: f64, p: f64) -> f64 {
    (x / x0 - 1.0).max(0.0).powf(p)
}

/// The base model's axial load scale on the paper's data (mN): the size a
/// drawn load is stated in.
pub fn load_scale_mn() -> f64 {
    Table::build(&Model::base(), &swimbot::data::paper())
        .expect("the base model predicts the paper")
        .load_scale(Place::LoadForce)
}

/// Condition `i` of a paper tail on the drawn design: channel 28-50 mm,
/// rate x0.8-1.6, tail length x0.9-1.3, drawn in that order.
pub fn vary(c: &Case, i: usize, r: &mut StdRng) -> Case {
    let mut v = c.clone();
    v.id = format!("{}-{i}", c.id);
    v.channel_diameter_mm = r.gen_range(28.0..50.0);
    v.frequency_hz *= r.gen_range(0.8..1.6);
    v.tail_length_mm *= r.gen_range(0.9..1.3);
    v
}

/// A fixture law: what a truth changes in the model, stage by stage (the
/// stages of `swimbot::effects::Effect`); every stage defaults to nothing.
pub trait Law: Copy + Send + Sync + 'static {
    fn local_drag(&self, _c: &Case, _drag: &mut LocalDrag) {}
    fn tail(&self, _c: &Case, _t: &mut Matrix6<f64>) {}
    fn body(&self, _c: &Case, _b: &mut Matrix6<f64>) {}
    fn balance(&self, _c: &Case, _fb: &mut ForceBalance) {}
}

/// A held-out truth as an effect of the model: the search never sees it.
pub struct Truth<L: Law>(pub L);

impl<L: Law> Effect for Truth<L> {
    fn name(&self) -> &str {
        "held-out-truth"
    }
    fn statement(&self) -> &str {
        "a held-out truth (docs/held-out.md, docs/held-out-2.md)"
    }
    fn reference(&self) -> &str {
        "held-out fixture"
    }
    fn local_drag(&self, _p: &[f64], c: &Case, drag: &mut LocalDrag) {
        self.0.local_drag(c, drag)
    }
    fn tail(&self, _p: &[f64], c: &Case, t: &mut Matrix6<f64>) -> Result<(), EffectError> {
        self.0.tail(c, t);
        Ok(())
    }
    fn body(&self, _p: &[f64], c: &Case, b: &mut Matrix6<f64>) {
        self.0.body(c, b)
    }
    fn balance(&self, _p: &[f64], c: &Case, fb: &mut ForceBalance) {
        self.0.balance(c, fb)
    }
}

/// Write a design as `<out>/<id>.toml` and return the SHA-256 of the text.
pub fn freeze(out: &str, id: &str, data: &Dataset) -> String {
    let text = swimbot::data::to_toml(data);
    std::fs::write(format!("{out}/{id}.toml"), &text).expect("write the design");
    sha256_hex(&text)
}

pub fn sha256_hex(text: &str) -> String {
    Sha256::digest(text.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The frozen hashes of a doc's table (`docs/<doc>`), by design: every
/// row whose last backquoted field is a SHA-256.
pub fn frozen_hashes(doc: &str) -> Vec<(String, String)> {
    let path = format!("{}/../docs/{doc}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    text.lines()
        .filter(|l| l.starts_with("| H"))
        .filter_map(|l| {
            let id = l.split('|').nth(1)?.trim().to_string();
            let hash = l.rsplit('`').nth(1)?.to_string();
            (hash.len() == 64 && hash.bytes().all(|b| b.is_ascii_hexdigit())).then_some((id, hash))
        })
        .collect()
}

/// Whether design `id` hashes as frozen; prints `<id> same` or `<id> DIFFERS`.
pub fn same_hash(frozen: &[(String, String)], id: &str, hex: &str) -> bool {
    let same = frozen.iter().any(|(i, h)| i == id && h == hex);
    println!("{id} {}", if same { "same" } else { "DIFFERS" });
    same
}

/// The expected verdict as the frozen tables state it.
pub fn expected(want: &[&str]) -> String {
    if want.is_empty() {
        "none-needed".to_string()
    } else {
        format!("located: {}", want.join(", "))
    }
}

/// A place and every place the verdict states as an equivalent reading of
/// a law there (`discovery::interpret::equivalents`: the reciprocal torque
/// pair, and the speed-only places read as one another); a catalogue
/// effect reads as itself.
pub fn readings(place: &str) -> Vec<&str> {
    let mut v = vec![place];
    if let Some(p) = Place::from_name(place) {
        v.extend(equivalents(p).iter().map(|e| e.place));
    }
    v
}

fn catalogue_places(name: &str) -> Vec<String> {
    match name {
        "buoyancy" => vec!["load.force".into()],
        "body-correction" => vec!["body.D_x".into(), "body.E_x".into()],
        _ => vec![name.into()],
    }
}

/// The sets a verdict states, each as sorted places.
pub fn sets_of(v: &Verdict) -> Vec<Vec<String>> {
    let raw: Vec<Vec<String>> = if !v.sets.is_empty() {
        v.sets.iter().map(|s| s.places.clone()).collect()
    } else {
        let mut found: Vec<String> = v.located.iter().map(|l| l.place.to_string()).collect();
        if let Some(e) = &v.effect {
            found.extend(e.split(" + ").map(str::to_string));
        }
        vec![found]
    };
    raw.into_iter()
        .map(|s| {
            let mut p: Vec<String> = s.iter().flat_map(|x| catalogue_places(x)).collect();
            p.sort();
            p.dedup();
            p
        })
        .collect()
}

/// Whether the truth's places are the set's read with its stated
/// readings, one member for each true place.
pub fn read_as(set: &[String], want: &[&str]) -> bool {
    fn assign(set: &[String], want: &[&str], used: &mut Vec<bool>) -> bool {
        let Some((w, rest)) = want.split_first() else {
            return true;
        };
        (0..set.len()).any(|i| {
            if used[i] || !readings(&set[i]).contains(w) {
                return false;
            }
            used[i] = true;
            let ok = assign(set, rest, used);
            used[i] = false;
            ok
        })
    }
    assign(set, want, &mut vec![false; set.len()])
}

/// Every true place read by a distinct member, and every member read as a
/// true place.
pub fn reads_exactly(set: &[String], want: &[&str]) -> bool {
    let covers = read_as(set, want);
    covers
        && set
            .iter()
            .all(|m| readings(m).iter().any(|r| want.contains(r)))
}

/// One verdict scored against the true places (`want` empty: the truth is
/// unobservable).
pub struct Score {
    pub sets: Vec<Vec<String>>,
    pub right: bool,
    pub with_rivals: bool,
    pub wrong_alone: bool,
    pub at_floor: bool,
}

pub fn score(v: &Verdict, want: &[&str]) -> Score {
    let sets = sets_of(v);
    let alone = matches!(v.kind, VerdictKind::Located | VerdictKind::Identified);
    let at_floor = match v.kind {
        VerdictKind::NoneNeeded => true,
        _ => v.steps.last().map_or(v.explained, |s| s.at_noise_floor),
    };
    let right = if want.is_empty() {
        v.kind == VerdictKind::NoneNeeded
    } else {
        alone && sets.len() == 1 && reads_exactly(&sets[0], want)
    };
    let with_rivals = !want.is_empty()
        && v.kind == VerdictKind::Indistinguishable
        && sets.iter().any(|s| reads_exactly(s, want));
    let wrong_alone = alone
        && sets.first().is_some_and(|s| {
            s.iter()
                .any(|m| !readings(m).iter().any(|r| want.contains(r)))
        });
    Score {
        sets,
        right,
        with_rivals,
        wrong_alone,
        at_floor,
    }
}

/// The counts over a batch.
#[derive(Default)]
pub struct Tally {
    pub right: u32,
    pub rivals: u32,
    pub wrong: u32,
    pub floor: u32,
    pub of: u32,
}

impl Tally {
    pub fn add(&mut self, s: &Score) {
        self.right += s.right as u32;
        self.rivals += s.with_rivals as u32;
        self.wrong += s.wrong_alone as u32;
        self.floor += s.at_floor as u32;
        self.of += 1;
    }

    pub fn line(&self) -> String {
        let n = self.of;
        format!(
            "right {}/{n}, stated with rivals {}/{n}, wrong alone {}/{n}, at the floor {}/{n}",
            self.right, self.rivals, self.wrong, self.floor
        )
    }
}

/// The stated sets, `/` between rivals.
pub fn stated(s: &Score) -> String {
    let v: Vec<String> = s.sets.iter().map(|x| x.join(", ")).collect();
    v.join(" / ")
}

/// Each found term's bootstrap selection frequency.
pub fn stability(v: &Verdict) -> String {
    let v: Vec<String> = v
        .stability
        .iter()
        .map(|t| format!("{} {:.2}", t.term, t.fraction))
        .collect();
    v.join(", ")
}
