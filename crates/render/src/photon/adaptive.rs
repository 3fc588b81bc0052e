//! Visibility-driven adaptive photon tracing (Hachisuka and Jensen 2011, "Robust adaptive
//! photon tracing using photon path visibility"): Markov chains in primary sample space whose
//! target is the indicator `V(u)` "the light path `u` stores a photon near a visible point"
//! ([`super::visible_points`]), so that a caustic seen in a small part of the image, or through
//! glass, gets the photons.
//!
//! # The sampler
//!
//! Each of [`CHAINS`] chains alternates two replicas at every step `j`:
//!
//! 1. a *uniform* light path `u_j` (the ordinary numbered path of the stream: the base emission,
//!    projection maps by default). It counts toward the normalisation
//!    `V_c = (visible uniform paths) / (uniform paths)`, the visible fraction of the base
//!    emission. If it is visible, the replicas exchange states: the chain jumps to `u_j`
//!    (replica exchange; it makes the chain ergodic, any visible region is reached by uniform
//!    sampling).
//! 2. Otherwise a *mutation* `u' = u + Δ` of the chain's state, every number perturbed by
//!    Kelemen et al.'s exponential step of size `d` (symmetric, so accepted iff `V(u') = 1`).
//!    `d` adapts toward an acceptance rate of 0.234 by a Robbins–Monro step of decreasing size
//!    (diminishing adaptation keeps the chain's limit).
//!
//! The chain's state at every step (once it has one) deposits its photons. Since the chain is
//! distributed as `V(u)/V_c` over the base emission's primary samples, a photon of base flux β
//! (the walker's flux, already divided by the base density) is stored with flux
//! `β V_c / M` for `M` chain steps: the chain stands for `N_eff = M / V_c` base light paths
//! ([`AdaptiveRun::equivalent_paths`]), and everything downstream (the photon flux β/N, the
//! photon differentials' `1/√N` of seed 002 eq. 5–6) uses `N_eff` as its path count. Only
//! visible photons are stored: the estimate at visible points is unchanged (up to the photons a
//! gather radius reaches beyond the visible points' radius of influence, docs/emission.md).
//!
//! # Determinism
//!
//! The chains run in waves until they have taken the requested number of steps with a state;
//! in a wave of `S` steps per chain, chain `c` owns the next uniform paths `c S … (c + 1) S − 1`
//! of the stream, and keeps its state, step size and mutation generator (seeded by
//! `(seed, stream, c)`) from wave to wave. Wave sizes depend only on counts, chains run in
//! parallel and are concatenated in chain order, so the result depends on the seed, not on the
//! thread count.

use crate::photon::plan::{PathStream, PhotonBudget};
use crate::photon::visible_points::VisiblePoints;
use crate::stats::RenderStats;
use caustica_core::sampling::sampler::ONE_MINUS_EPSILON;
use caustica_core::sampling::{Pcg32, Sampler, mix_seed};
use rayon::prelude::*;

/// Chains per pass (fixed, so the result does not depend on the thread count).
pub const CHAINS: u64 = 64;
/// The acceptance rate the mutation size adapts toward (Hachisuka and Jensen 2011, after
/// Roberts et al. 1997).
pub const TARGET_ACCEPTANCE: f64 = 0.234;
/// Initial mutation size, and its bounds.
const INITIAL_STEP: f64 = 0.05;
const MIN_STEP: f64 = 1e-4;
const MAX_STEP: f64 = 0.5;
/// Ratio of the largest to the smallest perturbation of Kelemen's mutation.
const STEP_RANGE: f32 = 64.0;
/// Tag of the mutations' random numbers.
const MUTATION_TAG: u64 = 0xADA9_7105;
/// Tag of the stream that positions the sampler for a mutated path's numbers beyond its state.
const PROPOSAL_STREAM_TAG: u64 = 0x9E37_79B9;

/// A chain state and the records its light path made, kept for `count` consecutive steps.
#[derive(Clone, Debug)]
pub struct ChainState<P> {
    /// The light path's numbers in primary sample space (replayed to trace it again).
    pub primary: Vec<f32>,
    pub records: Vec<P>,
    pub count: u32,
}

/// What the chains of one pass produced.
pub struct AdaptiveRun<P> {
    /// Chain states in chain order, then step order.
    pub states: Vec<ChainState<P>>,
    /// Chain steps with a state (`M`).
    pub steps: u64,
    /// Uniform paths traced, and how many were visible.
    pub uniform: u64,
    pub visible: u64,
    /// Mutations proposed and accepted.
    pub proposed: u64,
    pub accepted: u64,
    pub stats: RenderStats,
}

impl<P> AdaptiveRun<P> {
    fn empty() -> Self {
        AdaptiveRun {
            states: Vec::new(),
            steps: 0,
            uniform: 0,
            visible: 0,
            proposed: 0,
            accepted: 0,
            stats: RenderStats::default(),
        }
    }

    /// Adds the counts and states of `r` (a later chain or wave) to this run.
    fn absorb(&mut self, r: AdaptiveRun<P>) {
        self.states.extend(r.states);
        self.steps += r.steps;
        self.uniform += r.uniform;
        self.visible += r.visible;
        self.proposed += r.proposed;
        self.accepted += r.accepted;
        self.stats += r.stats;
    }

    /// `V_c`: the visible fraction of the base emission's light paths (uniform replicas).
    pub fn normalisation(&self) -> f64 {
        self.visible as f64 / self.uniform.max(1) as f64
    }

    /// `N_eff = M / V_c`: the base light paths the chains stand for (0 if none was visible).
    pub fn equivalent_paths(&self) -> f64 {
        if self.visible == 0 {
            0.0
        } else {
            self.steps as f64 / self.normalisation()
        }
    }

    /// Accepted mutations per proposed one.
    pub fn acceptance(&self) -> f64 {
        self.accepted as f64 / self.proposed.max(1) as f64
    }

    /// `N_eff` rounded: the path count of the pass's fluxes and footprints.
    pub fn paths(&self) -> u64 {
        self.equivalent_paths().round() as u64
    }

    /// The records of every state, each weighted by its repeat count (`weigh(record, count)`).
    pub fn weighted_records(&self, weigh: impl Fn(&P, f32) -> P) -> Vec<P> {
        self.states
            .iter()
            .flat_map(|s| s.records.iter().map(move |r| (r, s.count as f32)))
            .map(|(r, c)| weigh(r, c))
            .collect()
    }

    /// The render note: acceptance rate, normalisation, paths and the visible points.
    pub fn note(&self, visible: &VisiblePoints) -> String {
        format!(
            "adaptive photon tracing: {CHAINS} chains, {} steps, acceptance {:.1} % (target {:.1} %), visible fraction V_c = {:.4} from {} uniform paths ({} visible), {:.0} equivalent light paths; the visible points: {} within {:.4} m",
            self.steps,
            100.0 * self.acceptance(),
            100.0 * TARGET_ACCEPTANCE,
            self.normalisation(),
            self.uniform,
            self.visible,
            self.equivalent_paths(),
            visible.len(),
            visible.radius(),
        )
    }
}

/// The persistent part of one chain: its state, mutation generator and step size.
struct Chain<P> {
    rng: Pcg32,
    current: Option<(Vec<f32>, Vec<P>)>,
    log_step: f64,
    proposed: u64,
}

/// Runs the chains until they have taken `steps` steps with a state in all (about one photon
/// each), in waves whose sizes depend only on counts, over
/// light paths from `first` on of `stream`: `trace(sampler, records, stats)` traces one light
/// path with the sampler positioned (and, for mutations, replaying a state),
/// `visible(records)` says whether the path is visible. A state is the numbers its path drew
/// (extended lazily when a mutated path draws more); the states keep them only with
/// `keep_primary` (pds replays them; the photon maps need only the records). Gives up, like
/// the other passes, after [`MAX_UNIFORM_PER_STEP`] uniform paths per requested step.
pub fn run_chains<P: Clone + Send>(
    stream: &PathStream,
    first: u64,
    steps: u64,
    keep_primary: bool,
    visible: &(impl Fn(&[P]) -> bool + Sync),
    trace: &(impl Fn(&mut Sampler, &mut Vec<P>, &mut RenderStats) + Sync),
) -> AdaptiveRun<P> {
    let mut chains: Vec<Chain<P>> = (0..CHAINS)
        .map(|c| Chain {
            rng: Pcg32::new(mix_seed(stream.seed, &[stream.stream, c, MUTATION_TAG]), c),
            current: None,
            log_step: INITIAL_STEP.ln(),
            proposed: 0,
        })
        .collect();
    let mut all = AdaptiveRun::empty();
    let mut next_path = first;
    while all.steps < steps && all.uniform < steps.saturating_mul(MAX_UNIFORM_PER_STEP) {
        // Steps per chain in this wave: what is missing shared by all chains (each deposits
        // every step once it has a state), at least 16; waves repeat until enough.
        let per_chain = (steps - all.steps).div_ceil(CHAINS).clamp(16, 1 << 20);
        let wave_first = next_path;
        next_path += per_chain * CHAINS;
        let runs: Vec<AdaptiveRun<P>> = chains
            .par_iter_mut()
            .enumerate()
            .map(|(c, chain)| {
                run_chain(
                    chain,
                    stream,
                    wave_first + c as u64 * per_chain,
                    per_chain,
                    keep_primary,
                    visible,
                    trace,
                )
            })
            .collect();
        for r in runs {
            all.absorb(r);
        }
    }
    all
}

/// The chain steps of a caustic pass's budget: about one photon per step, or one step per
/// light path of a fixed budget.
pub fn chain_steps(budget: PhotonBudget) -> u64 {
    match budget {
        PhotonBudget::Records(n) => n as u64,
        PhotonBudget::Paths(n) => n,
    }
}

/// Uniform paths per requested chain step after which the chains give up (no light path is
/// visible: the caustic is not seen, or too rarely to find).
pub const MAX_UNIFORM_PER_STEP: u64 = 1 << 10;

fn run_chain<P: Clone>(
    chain: &mut Chain<P>,
    stream: &PathStream,
    first: u64,
    steps: u64,
    keep_primary: bool,
    visible: &impl Fn(&[P]) -> bool,
    trace: &impl Fn(&mut Sampler, &mut Vec<P>, &mut RenderStats),
) -> AdaptiveRun<P> {
    let mut sampler = Sampler::new(stream.sampler, stream.seed);
    let mut run = AdaptiveRun::empty();
    let rng = &mut chain.rng;
    let mut changed = true;
    let mut records = Vec::new();
    for j in 0..steps {
        // 1. The uniform replica: path first + j of the stream, its numbers recorded.
        let path = first + j;
        sampler.start_path(stream.stream, path);
        sampler.replay_primary(Vec::new());
        records.clear();
        trace(&mut sampler, &mut records, &mut run.stats);
        let primary = sampler.take_primary();
        run.uniform += 1;
        run.stats.samples += 1;
        if visible(&records) {
            run.visible += 1;
            // Replica exchange: the chain jumps to the visible uniform path.
            chain.current = Some((primary, records.clone()));
            changed = true;
        } else if let Some((state, _)) = &chain.current {
            // 2. A mutation of the chain's state: its numbers perturbed; numbers the mutated
            // path draws beyond them are fresh (a lazily extended state).
            let d = chain.log_step.exp() as f32;
            let proposal: Vec<f32> = state.iter().map(|&x| perturb(x, d, rng)).collect();
            sampler.start_path(stream.stream ^ PROPOSAL_STREAM_TAG, path);
            sampler.replay_primary(proposal);
            records.clear();
            trace(&mut sampler, &mut records, &mut run.stats);
            let proposal = sampler.take_primary();
            run.proposed += 1;
            chain.proposed += 1;
            let accepted = visible(&records);
            if accepted {
                run.accepted += 1;
                chain.current = Some((proposal, records.clone()));
                changed = true;
            }
            // Robbins–Monro on log d, step size decreasing with the chain's proposals.
            let gain = 1.0 / (1.0 + chain.proposed as f64).powf(0.6);
            chain.log_step = (chain.log_step + gain * (accepted as u8 as f64 - TARGET_ACCEPTANCE))
                .clamp(MIN_STEP.ln(), MAX_STEP.ln());
        }
        // 3. The chain's state deposits its records.
        if let Some((state, recs)) = &chain.current {
            run.steps += 1;
            match run.states.last_mut() {
                Some(last) if !changed => last.count += 1,
                _ => run.states.push(ChainState {
                    primary: if keep_primary {
                        state.clone()
                    } else {
                        Vec::new()
                    },
                    records: recs.clone(),
                    count: 1,
                }),
            }
            changed = false;
        }
    }
    run
}

/// Kelemen et al.'s symmetric perturbation of one primary sample: a step of size between
/// `d / STEP_RANGE` and `d`, exponentially distributed in between, either way, wrapped into
/// [0, 1).
fn perturb(x: f32, d: f32, rng: &mut Pcg32) -> f32 {
    let dv = d * (-(STEP_RANGE.ln()) * rng.next_f32()).exp();
    let y = if rng.next_f32() < 0.5 { x + dv } else { x - dv };
    (y - y.floor()).min(ONE_MINUS_EPSILON)
}
