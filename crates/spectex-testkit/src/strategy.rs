//! Number and list strategies drawn around and beyond a field's valid range: mostly inside it
//! (uniform, log-uniform, near zero, the bounds themselves), and with the case's [`Odds`] just
//! outside it, far outside it, NaN, ±∞, −0, subnormals or any bit pattern.

use proptest::prelude::*;

/// How often a field is drawn outside its valid range, in draws per 1000. One value per case
/// (see [`odds`]): most cases are fully valid so that evaluation is exercised, the others break
/// few or many fields so that validation is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Odds {
    /// Out-of-range draws per 1000.
    pub bad: u32,
}

impl Odds {
    /// Every field inside its range.
    pub const VALID: Self = Self { bad: 0 };
}

/// The odds of a case: 0 (every field valid) half the time, else 5, 40 or 200 per 1000.
pub fn odds() -> impl Strategy<Value = Odds> {
    prop_oneof![
        6 => Just(Odds::VALID),
        2 => Just(Odds { bad: 5 }),
        2 => Just(Odds { bad: 40 }),
        2 => Just(Odds { bad: 200 }),
    ]
}

/// `inside` with probability `1 − bad/1000`, else `outside`.
fn mix<T: std::fmt::Debug + Clone + 'static>(
    odds: Odds,
    inside: BoxedStrategy<T>,
    outside: BoxedStrategy<T>,
) -> BoxedStrategy<T> {
    if odds.bad == 0 {
        inside
    } else {
        prop_oneof![1000 - odds.bad.min(999) => inside, odds.bad.min(999) => outside].boxed()
    }
}

/// An `f32` for a field whose valid range is `[lo, hi]` (finite, `lo < hi`).
pub fn f32_in(lo: f32, hi: f32, odds: Odds) -> BoxedStrategy<f32> {
    mix(odds, f32_inside(lo, hi), f32_outside(lo, hi))
}

/// An `f32` inside `[lo, hi]`: uniform; log-uniform in magnitude (ranges spanning decades, like
/// `[0.5, 1e6]` pixels, are otherwise almost always drawn near their top); within `[−1, 1]`
/// where the range allows; and the bounds.
pub fn f32_inside(lo: f32, hi: f32) -> BoxedStrategy<f32> {
    debug_assert!(lo < hi, "[{lo}, {hi}]");
    let unit = (lo.max(-1.0), hi.min(1.0));
    let mut choices: Vec<(u32, BoxedStrategy<f32>)> = vec![
        (3, (lo..=hi).boxed()),
        (3, log_uniform(lo, hi)),
        (1, Just(lo).boxed()),
        (1, Just(hi).boxed()),
    ];
    if unit.0 < unit.1 {
        choices.push((3, (unit.0..=unit.1).boxed()));
    }
    proptest::strategy::Union::new_weighted(choices).boxed()
}

/// Magnitudes spread evenly over the decades of `[lo, hi]` (signed when the range holds both
/// signs), clamped into the range.
fn log_uniform(lo: f32, hi: f32) -> BoxedStrategy<f32> {
    let top = f64::from(lo.abs().max(hi.abs())).max(1e-30);
    let bottom = if lo > 0.0 {
        f64::from(lo)
    } else if hi < 0.0 {
        f64::from(hi.abs())
    } else {
        top * 1e-9
    };
    let (a, b) = (bottom.min(top).log2(), top.log2());
    let (a, b) = if a < b { (a, b) } else { (a, a + 1.0) };
    (a..=b, any::<bool>())
        .prop_map(move |(e, negative)| {
            let v = e.exp2() as f32;
            let v = if negative && lo < 0.0 { -v } else { v };
            v.clamp(lo, hi)
        })
        .boxed()
}

/// An `f32` just outside `[lo, hi]`, far outside it, or not a number at all.
pub fn f32_outside(lo: f32, hi: f32) -> BoxedStrategy<f32> {
    let span = (hi - lo).abs().max(1.0);
    prop_oneof![
        Just(lo.next_down()),
        Just(hi.next_up()),
        Just(lo - span),
        Just(hi + span),
        Just(hi * 1e3 + span),
        Just(-1e30f32),
        Just(1e30f32),
        Just(f32::MAX),
        Just(f32::MIN),
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(f32::NEG_INFINITY),
        Just(-0.0f32),
        Just(f32::from_bits(1)),
        any::<u32>().prop_map(f32::from_bits),
    ]
    .boxed()
}

/// A `u32` for a field whose valid range is `lo..=hi`: inside (uniform, and the bounds), or
/// just outside, 0, `u32::MAX` or anything.
pub fn u32_in(lo: u32, hi: u32, odds: Odds) -> BoxedStrategy<u32> {
    let inside = prop_oneof![4 => lo..=hi, 1 => Just(lo), 1 => Just(hi)].boxed();
    let outside = prop_oneof![
        Just(lo.wrapping_sub(1)),
        Just(hi.wrapping_add(1)),
        Just(0u32),
        Just(u32::MAX),
        Just(hi.saturating_mul(2)),
        any::<u32>(),
    ]
    .boxed();
    mix(odds, inside, outside)
}

/// A `u32` from `typical` (valid values a model usually takes, e.g. powers of two), or with the
/// case's odds from `bad` values.
pub fn u32_from(typical: &[u32], bad: &[u32], odds: Odds) -> BoxedStrategy<u32> {
    let inside = proptest::sample::select(typical.to_vec()).boxed();
    let mut outside = bad.to_vec();
    outside.extend([0, u32::MAX]);
    mix(
        odds,
        inside,
        prop_oneof![proptest::sample::select(outside), any::<u32>()].boxed(),
    )
}

/// A list of `element`s for a field whose valid length is `min..=max`: usually
/// `min..=typical` long; with the case's odds empty, or `max + 1` or `max` copies of one
/// element (when that many are cheap: `max` up to [`HUGE_LIST`]).
pub fn list<T: std::fmt::Debug + Clone + 'static>(
    element: BoxedStrategy<T>,
    min: usize,
    typical: usize,
    max: usize,
    odds: Odds,
) -> BoxedStrategy<Vec<T>> {
    let typical = typical.clamp(min, max);
    let inside = proptest::collection::vec(element.clone(), min..=typical).boxed();
    let mut outside: Vec<BoxedStrategy<Vec<T>>> = vec![Just(Vec::new()).boxed()];
    if max <= HUGE_LIST {
        // Copies of one element: drawing thousands of independent ones (each a value tree,
        // nested lists multiplying) would make one case cost seconds.
        outside.push(element.clone().prop_map(move |e| vec![e; max + 1]).boxed());
        outside.push(element.prop_map(move |e| vec![e; max]).boxed());
    }
    mix(
        odds,
        inside,
        proptest::strategy::Union::new(outside).boxed(),
    )
}

/// Longest list a strategy builds element by element (`max + 1` for the lists whose limit is
/// at most this); longer limits (a table's 2²⁰ frequencies) are probed by the explicit limit
/// cases of [`crate::limits`].
pub const HUGE_LIST: usize = 4097;
