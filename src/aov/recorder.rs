//! The recorder of an AOV render: no nodes, only each contribution's light path expression
//! (matched against the AOVs' expressions, each distinct path string once) and how each path
//! ended.

use crate::integrator::Recorder;
use crate::lpe::Lpe;
use crate::math::Rgb;
use crate::tree::{EndReason, NodeId, RayNode};
use std::collections::HashMap;

/// At most this many AOVs (one bit each in the match cache).
pub const MAX_AOVS: usize = 64;

/// Splits one sample's radiance by light path expression: [`AovRecorder::sample`] holds, for
/// each expression, the sum of the sample's contributions whose path matches it. Records no
/// node ([`Recorder::RECORDS`] is false), so the tracer does none of the tree's bookkeeping;
/// the path integrator builds the path strings and calls [`Recorder::contribution`]. Reuse
/// one per thread; [`AovRecorder::start_sample`] before each sample.
#[derive(Clone, Debug)]
pub struct AovRecorder<'a> {
    lpes: &'a [Lpe],
    /// Path string -> bit `k` set when it matches `lpes[k]`.
    cache: HashMap<String, u64>,
    key: String,
    /// This sample's contributions per expression.
    pub sample: Vec<Rgb>,
    /// This sample's path rays (camera ray and continuations).
    pub segments: u32,
    /// Whether Russian roulette ended this sample's path.
    pub roulette: bool,
}

impl<'a> AovRecorder<'a> {
    /// A recorder for `lpes` (at most [`MAX_AOVS`]).
    ///
    /// # Panics
    /// If there are more than [`MAX_AOVS`] expressions.
    #[must_use]
    pub fn new(lpes: &'a [Lpe]) -> Self {
        assert!(lpes.len() <= MAX_AOVS, "at most {MAX_AOVS} AOVs");
        Self {
            lpes,
            cache: HashMap::new(),
            key: String::new(),
            sample: vec![Rgb::ZERO; lpes.len()],
            segments: 0,
            roulette: false,
        }
    }

    /// Forget the last sample.
    pub fn start_sample(&mut self) {
        self.sample.fill(Rgb::ZERO);
        self.segments = 0;
        self.roulette = false;
    }

    /// The expressions `path` matches, a bit each.
    fn mask(&mut self, path: &str) -> u64 {
        if let Some(m) = self.cache.get(path) {
            return *m;
        }
        let m = self
            .lpes
            .iter()
            .enumerate()
            .filter(|(_, l)| l.matches(path))
            .fold(0u64, |m, (k, _)| m | (1 << k));
        self.cache.insert(path.to_owned(), m);
        m
    }
}

impl Recorder for AovRecorder<'_> {
    const RECORDS: bool = false;
    const DIAGNOSE: bool = false;
    const PATHS: bool = true;

    #[inline(always)]
    fn push(&mut self, _: Option<NodeId>, _: impl FnOnce() -> RayNode) -> Option<NodeId> {
        None
    }

    #[inline(always)]
    fn update(&mut self, _: Option<NodeId>, _: impl FnOnce(&mut RayNode)) {}

    fn contribution(&mut self, lpe: &str, event: &str, end: char, c: Rgb) {
        if c == Rgb::ZERO || self.lpes.is_empty() {
            return;
        }
        let mut key = std::mem::take(&mut self.key);
        key.clear();
        key.push_str(lpe);
        key.push_str(event);
        key.push(end);
        let mut mask = self.mask(&key);
        self.key = key;
        while mask != 0 {
            let k = mask.trailing_zeros() as usize;
            self.sample[k] += c;
            mask &= mask - 1;
        }
    }

    fn path_end(&mut self, segments: u32, reason: EndReason) {
        self.segments += segments;
        self.roulette |= reason == EndReason::RussianRoulette;
    }
}
