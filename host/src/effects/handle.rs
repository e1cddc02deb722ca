//! A cheap-to-clone handle on an effect, as an [`super::EffectInstance`]
//! holds it: a compiled-in effect is borrowed for the whole program, an
//! effect built at run time (a user's formulas, a located correction) is
//! shared and freed with the last model that holds it, so a long session
//! that parses many formulas does not keep every one of them.

use super::Effect;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// Identities of run-time effects: an address can be reused once an effect
/// is freed, a number from this counter is never.
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// An effect, compiled-in or built at run time.
#[derive(Clone)]
pub enum EffectRef {
    /// A catalogue effect: a unit struct that lives as long as the program.
    Builtin(&'static dyn Effect),
    /// An effect built at run time, shared by the models that use it, with
    /// its identity (the same for every clone of this handle).
    Shared(Arc<dyn Effect>, u64),
}

impl EffectRef {
    /// A run-time effect, with a new identity.
    pub fn shared(effect: Arc<dyn Effect>) -> Self {
        EffectRef::Shared(effect, NEXT_ID.fetch_add(1, Ordering::Relaxed))
    }

    /// Identifies the effect within the process: two handles with one
    /// identity are the same effect (the key of a model's attached
    /// quantities, [`crate::model::columns::key`]).
    pub fn identity(&self) -> u64 {
        match self {
            // Compiled-in effects never move or go; their address, shifted,
            // is even and run-time identities are odd, so the two never
            // meet. Two zero-sized compiled-in effects may share an
            // address: a key that must tell them apart hashes the name too.
            EffectRef::Builtin(e) => (*e as *const dyn Effect as *const () as usize as u64) << 1,
            EffectRef::Shared(_, id) => (id << 1) | 1,
        }
    }
}

impl std::ops::Deref for EffectRef {
    type Target = dyn Effect;
    fn deref(&self) -> &(dyn Effect + 'static) {
        match self {
            EffectRef::Builtin(e) => *e,
            EffectRef::Shared(e, _) => e.as_ref(),
        }
    }
}

impl From<&'static dyn Effect> for EffectRef {
    fn from(e: &'static dyn Effect) -> Self {
        EffectRef::Builtin(e)
    }
}

impl<T: Effect + 'static> From<Arc<T>> for EffectRef {
    fn from(e: Arc<T>) -> Self {
        EffectRef::shared(e)
    }
}

impl From<Arc<dyn Effect>> for EffectRef {
    fn from(e: Arc<dyn Effect>) -> Self {
        EffectRef::shared(e)
    }
}

impl<T: Effect + 'static> From<&'static T> for EffectRef {
    fn from(e: &'static T) -> Self {
        EffectRef::Builtin(e)
    }
}
