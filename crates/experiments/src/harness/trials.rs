//! Deterministic parallel Monte Carlo: trials are cut into fixed-size chunks,
//! each chunk draws from its own PCG32 stream keyed by (experiment seed,
//! chunk index, stream), and the chunk results are merged in chunk order.
//! The chunking depends on the trial count only, never on the thread count,
//! so every experiment gives bit-identical numbers on any machine.

use fogbank_math::{Pcg32, SampleKey};
use rayon::prelude::*;

/// Trials per chunk: large enough that scheduling is negligible, small
/// enough that 2 cores stay balanced for 10⁴-trial runs.
pub const CHUNK: u64 = 4096;

/// Runs `trials` trials. `body(rng, acc, count)` performs `count` trials of
/// one chunk into a fresh accumulator from `init`; `merge` folds the chunk
/// accumulators in chunk order.
pub fn run_chunked<A: Send>(
    trials: u64,
    seed: u32,
    stream: u32,
    init: impl Fn() -> A + Sync,
    body: impl Fn(&mut Pcg32, &mut A, u64) + Sync,
    merge: impl Fn(&mut A, A),
) -> A {
    let chunks = trials.div_ceil(CHUNK);
    let parts: Vec<A> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut rng = SampleKey {
                seed,
                pixel: c as u32,
                sample: (c >> 32) as u32,
                dimension: stream,
            }
            .rng();
            let mut acc = init();
            let count = CHUNK.min(trials - c * CHUNK);
            body(&mut rng, &mut acc, count);
            acc
        })
        .collect();
    let mut total = init();
    for p in parts {
        merge(&mut total, p);
    }
    total
}

/// Running first and second moments of a sample (sums in f64; the values
/// here are O(1), so 10⁸ terms lose at most ~10⁻⁸ relative precision).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moments {
    pub n: u64,
    pub sum: f64,
    pub sum_sq: f64,
}

impl Moments {
    #[inline]
    pub fn push(&mut self, x: f64) {
        self.n += 1;
        self.sum += x;
        self.sum_sq += x * x;
    }

    pub fn merge(&mut self, o: Moments) {
        self.n += o.n;
        self.sum += o.sum;
        self.sum_sq += o.sum_sq;
    }

    pub fn mean(&self) -> f64 {
        self.sum / self.n.max(1) as f64
    }

    /// Sample standard deviation (n − 1 in the denominator).
    pub fn std(&self) -> f64 {
        if self.n < 2 {
            return 0.0;
        }
        let m = self.mean();
        ((self.sum_sq - self.n as f64 * m * m) / (self.n - 1) as f64)
            .max(0.0)
            .sqrt()
    }

    /// Standard error of the mean.
    pub fn std_error(&self) -> f64 {
        self.std() / (self.n.max(1) as f64).sqrt()
    }

    /// Root mean square deviation from `reference`.
    pub fn rms_about(&self, reference: f64) -> f64 {
        let n = self.n.max(1) as f64;
        ((self.sum_sq - 2.0 * reference * self.sum) / n + reference * reference)
            .max(0.0)
            .sqrt()
    }
}
