//! What every model kind provides at the model layer ([`ModelKind`]), and the one registry of
//! kinds ([`for_each_kind!`](crate::for_each_kind)) that [`Model`]'s methods dispatch through.
//!
//! A kind is a struct (its serde type, in its own module) implementing [`ModelKind`], plus its
//! variant of [`Model`] and its line in `for_each_kind!`, both in this file; [`KIND_NAMES`]
//! and [`PERIODIC_KINDS`] are collected from the kinds through the macro. Nothing else in this crate matches over [`Model`], and the other
//! crates reach a kind through their own per-kind traits with one dispatch each.

use std::sync::LazyLock;

use serde::{Deserialize, Serialize};

use crate::error::ModelError;
use crate::period::Period;
use crate::{
    ClassicNoise, Combine, GaborNoise, IslamicPattern, LrpNoise, MatrixTransform, PhasorNoise,
    StochasticSubdivision, TextonNoise, TextureModel, TilingTexture, VoronoiNoise, Warp,
    WaveletNoise,
};

/// The model-layer definition of one kind: its name, validation, output channels and seeds.
pub trait ModelKind {
    /// The kind's name: its tag in model files (`{"lrp": …}`), in messages, registries and docs.
    const NAME: &'static str;

    /// Checks every field.
    ///
    /// # Errors
    /// The first field found outside its range, with its dotted path.
    fn validate(&self) -> Result<(), ModelError>;

    /// Whether the kind has a periodic form ([`check_period`](Self::check_period) accepts some
    /// periods); what [`PERIODIC_KINDS`] lists. A kind that overrides `check_period` says
    /// `true` (a test in `spectex-cpu` holds the two together).
    const PERIODIC: bool = false;

    /// Values per pixel: 1 (grey) unless the kind says otherwise (a colour texture gives 3).
    fn output_channels(&self) -> usize {
        1
    }

    /// Calls `visit` on every seed the model holds, nested models' included, in a fixed order.
    fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32));

    /// Checks that the model can be made exactly periodic with `period` ([`crate::period`]).
    /// The default refuses: a kind without a periodic form says so.
    ///
    /// # Errors
    /// [`ModelError::Period`] saying what the kind needs of a period.
    fn check_period(&self, period: Period) -> Result<(), ModelError> {
        Err(ModelError::Period {
            period: period.to_string(),
            kind: Self::NAME,
            requirement: format!(
                "{} models have no periodic form yet (periodic kinds: {})",
                Self::NAME,
                PERIODIC_KINDS.join(", ")
            ),
        })
    }
}

/// The kinds that have a periodic form ([`ModelKind::PERIODIC`]), in the order of [`Model`]'s
/// variants: for messages and tests.
pub static PERIODIC_KINDS: LazyLock<Vec<&'static str>> = LazyLock::new(|| {
    let mut kinds = Vec::new();
    crate::for_each_kind!(types: K => {
        if <K as ModelKind>::PERIODIC {
            kinds.push(<K as ModelKind>::NAME);
        }
    });
    kinds
});

/// Any procedural model spectex evaluates: one variant per kind, each a [`crate::ModelKind`].
///
/// Deliberately not `#[non_exhaustive]`: a `match` over it in another crate must name every
/// kind, so the compiler points at each place a new kind is missed (the tidy test forbids
/// wildcard arms over `Model` outside this crate).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
#[allow(
    clippy::large_enum_variant,
    reason = "a model is built once per render and never stored in bulk"
)]
pub enum Model {
    /// Local Random-Phase noise.
    Lrp(LrpNoise),
    /// Gabor noise.
    Gabor(GaborNoise),
    /// Phasor noise.
    Phasor(PhasorNoise),
    /// Texture by example: structure, strata, turbulence, placement, colour.
    Texture(TextureModel),
    /// A classic pointwise noise (gradient, simplex, value, Worley; fractal sums of them).
    Classic(ClassicNoise),
    /// Domain warping: a model evaluated at positions displaced by two others
    /// ([`crate::warp`]).
    Warp(Warp),
    /// Wavelet noise (Cook & DeRose 2005): a band-limited tile summed over octave bands.
    Wavelet(WaveletNoise),
    /// Texton placement and spot noise (survey §2.3, §3.1.5).
    Texton(TextonNoise),
    /// Voronoi diagrams (survey §2.6): cell IDs, distances, borders, colours.
    Voronoi(VoronoiNoise),
    /// A pointwise combination of models (survey §4.1–4.2, [`crate::combine`]).
    Combine(Combine),
    /// Islamic star patterns on regular tilings (survey §2.7, [`crate::islamic`]).
    Islamic(IslamicPattern),
    /// Matrix transformation (survey §2.4, [`crate::matrix`]): a source moved `k` times by an
    /// integer matrix on the `N × N` torus.
    Matrix(MatrixTransform),
    /// Stochastic subdivision (survey §3.1.7, [`crate::subdivision`]): midpoint displacement
    /// on a square lattice, each displacement a hash of its level and lattice point.
    Subdivision(StochasticSubdivision),
    /// Tiling and blending by example (Heitz & Neyret 2018, [`crate::tiling`]): an exemplar's
    /// tiles on a triangle lattice, blended so the histogram is kept.
    Tiling(TilingTexture),
}

/// The one list of kinds: a kind is its line here (module, [`Model`] variant, struct) and its
/// variant of [`Model`]; every layer reaches its kinds through this macro.
///
/// - `for_each_kind!(model, m: K => body)` calls `body` with `m` bound to the kind struct inside
///   `model` (by the reference the match gives) and `K` naming its type.
/// - `for_each_kind!(types: K => body)` runs `body` once per kind, in the order of [`Model`]'s
///   variants, with only `K` bound: how each layer collects what its kinds declare (their
///   names, periodic forms, shaders, test strategies) instead of keeping a list of its own.
/// - `for_each_kind!(VIS mod);` declares `VIS mod <kind>;` for every kind, in the module that
///   invokes it (files `<kind>.rs` beside that module's file, or in its folder, as for any
///   `mod`): each layer's one module per kind. rustfmt does not see modules a macro declares,
///   so `cargo xtask fmt` formats them (and `cargo xtask ci` checks them).
/// - `for_each_kind!(pub use);` re-exports each kind struct at the invoking module (the crate
///   root of `spectex-model`).
/// - `for_each_kind!(list: callback);` calls the caller's `callback! { module Variant Type, … }`
///   (`Type` a path): for a layer that generates items per kind (the command line's
///   subcommands).
#[macro_export]
#[doc(hidden)]
macro_rules! for_each_kind {
    (types: $Kind:ident => $body:expr) => {
        $crate::for_each_kind! { @kinds [types $Kind $body] }
    };
    (pub use) => {
        $crate::for_each_kind! { @kinds [use] }
    };
    ($vis:vis mod) => {
        $crate::for_each_kind! { @kinds [$vis mod] }
    };
    (list: $callback:ident) => {
        $crate::for_each_kind! { @kinds [list $callback] }
    };
    // The list: `module Variant Struct`, in the order of `Model`'s variants.
    (@kinds $form:tt) => {
        $crate::for_each_kind! { @each $form
            lrp Lrp LrpNoise,
            gabor Gabor GaborNoise,
            phasor Phasor PhasorNoise,
            texture Texture TextureModel,
            classic Classic ClassicNoise,
            warp Warp Warp,
            wavelet Wavelet WaveletNoise,
            texton Texton TextonNoise,
            voronoi Voronoi VoronoiNoise,
            combine Combine Combine,
            islamic Islamic IslamicPattern,
            matrix Matrix MatrixTransform,
            subdivision Subdivision StochasticSubdivision,
            tiling Tiling TilingTexture,
        }
    };
    (@each [types $Kind:ident $body:expr] $($module:ident $Variant:ident $Struct:ident,)*) => {{
        $({
            type $Kind = $crate::$module::$Struct;
            $body;
        })*
    }};
    (@each [match $model:expr, $m:ident, $Kind:ident, $body:expr]
        $($module:ident $Variant:ident $Struct:ident,)*) => {
        match $model {
            $($crate::Model::$Variant($m) => {
                type $Kind = $crate::$module::$Struct;
                $body
            })*
        }
    };
    (@each [$vis:vis mod] $($module:ident $Variant:ident $Struct:ident,)*) => {
        $($vis mod $module;)*
    };
    (@each [use] $($module:ident $Variant:ident $Struct:ident,)*) => {
        $(pub use $crate::$module::$Struct;)*
    };
    (@each [list $callback:ident] $($module:ident $Variant:ident $Struct:ident,)*) => {
        $callback! { $($module $Variant $crate::$module::$Struct,)* }
    };
    ($model:expr, $m:ident : $Kind:ident => $body:expr) => {
        $crate::for_each_kind! { @kinds [match $model, $m, $Kind, $body] }
    };
}

/// The names of every kind, in the order of [`Model`]'s variants (for registries, docs and the
/// tidy test that keeps the docs' list of kinds true).
pub static KIND_NAMES: LazyLock<Vec<&'static str>> = LazyLock::new(|| {
    let mut names = Vec::new();
    for_each_kind!(types: K => names.push(<K as ModelKind>::NAME));
    names
});

impl Model {
    /// The kind's name ([`ModelKind::NAME`]): `"lrp"`, `"classic"`, … (the model file's tag).
    #[must_use]
    pub fn kind(&self) -> &'static str {
        for_each_kind!(self, _m: K => <K as ModelKind>::NAME)
    }

    /// Checks every field of the model.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        for_each_kind!(self, m: K => <K as ModelKind>::validate(m))
    }

    /// Values per pixel: 3 for a colour texture (or a warp of one), else 1.
    #[must_use]
    pub fn output_channels(&self) -> usize {
        for_each_kind!(self, m: K => <K as ModelKind>::output_channels(m))
    }

    /// Checks that the model can be made exactly periodic with `period`
    /// ([`ModelKind::check_period`]).
    ///
    /// # Errors
    /// [`ModelError::Period`] saying what the kind needs of a period.
    pub fn check_period(&self, period: Period) -> Result<(), ModelError> {
        for_each_kind!(self, m: K => <K as ModelKind>::check_period(m, period))
    }

    /// Calls `visit` on every seed of the model, nested models' included.
    pub fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32)) {
        for_each_kind!(self, m: K => <K as ModelKind>::visit_seeds(m, visit));
    }

    /// The same model with every seed it holds (nested models' too) advanced by `delta`,
    /// wrapping: an independent copy of the same noise (same spectrum and parameters).
    #[must_use]
    pub fn reseeded(&self, delta: u32) -> Self {
        let mut model = self.clone();
        model.visit_seeds(&mut |seed| *seed = seed.wrapping_add(delta));
        model
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::fixtures;

    pub fn kind_names_are_the_model_file_tags() {
        for model in [
            Model::Lrp(fixtures::lrp_four_strata(10)),
            Model::Gabor(fixtures::gabor_isotropic()),
            fixtures::constant(0.5),
        ] {
            let json = crate::to_json(&model).expect("valid fixture");
            let value: serde_json::Value = serde_json::from_str(&json).expect("JSON");
            let tag = value["model"]
                .as_object()
                .and_then(|o| o.keys().next().cloned())
                .expect("one tag");
            assert_eq!(tag, model.kind());
            assert!(KIND_NAMES.contains(&model.kind()));
        }
        let mut sorted = KIND_NAMES.to_vec();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), KIND_NAMES.len(), "kind names are distinct");
    }

    /// Every layer finds a kind's files by its module name (`<kind>.rs`, declared by
    /// `for_each_kind!(mod)`), and the docs and registries by its name: they are one.
    pub fn each_kind_lives_in_the_module_of_its_name() {
        for_each_kind!(types: K => {
            let path = std::any::type_name::<K>();
            assert_eq!(
                path.split("::").nth(1),
                Some(<K as ModelKind>::NAME),
                "{path}: the kind's module and its name differ"
            );
        });
    }
}
