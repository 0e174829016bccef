//! Turns a target spectrum into a procedural model: equal-energy stratification of a power
//! spectrum, erosion, k-means sub-strata, amplitudes, structure-region selection and block
//! subdivision (Gilet et al. 2014, §4–5), and the fitting of Gabor, LRP and phasor models.
//!
//! Depends on `spectex-model` (the types it produces) and `spectex-spectrum` (the analyses it
//! reads). Nothing is implemented here yet: the Local Random-Phase noise issue fills it.
