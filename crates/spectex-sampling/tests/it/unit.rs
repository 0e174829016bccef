//! The crate's unit tests: their bodies are `pub mod tests` in the source modules (behind the
//! `unit-tests` feature, so the crate is compiled once for both its tests and its dependents),
//! run here one `#[test]` each. `every_unit_test_is_run` fails when a body has no `#[test]`
//! here, or a `#[test]` here names no body.

/// One module per source module, one `#[test]` per body, and the list of every name.
macro_rules! unit_tests {
    ($($module:ident: $($test:ident),+;)+) => {
        $(
            mod $module {
                $(
                    #[test]
                    fn $test() {
                        spectex_sampling::unit_tests::$module::$test();
                    }
                )+
            }
        )+
        const RUN: &[&str] = &[$($(stringify!($test)),+),+];
    };
}

unit_tests! {
    amplitude: lattice_mean_of_squared_windows_is_two_pi_c, amplitude_gives_the_stratum_energy_as_variance;
    erosion: distance_transform_matches_the_direct_minimum, components_match_their_definition, erosion_matches_the_direct_modified_definition, a_thin_ring_keeps_its_centre_line_all_the_way_round, a_full_grid_and_an_empty_set_are_left_alone;
    fit: options_are_validated_with_their_name_and_range, fitted_psd_keeps_budget_energy_and_ranges, eroded_strata_are_inside_their_strata_and_symmetric, targets_are_fitted_with_the_requested_variance, bad_inputs_are_errors_not_panics, a_stratum_of_one_frequency_gets_one_cosine, a_pure_sinusoid_gets_one_stratum_of_one_frequency_pair;
    from_target: defaults_are_the_documented_constants_and_fit_target_with_them, given_options_replace_the_defaults, invalid_options_name_the_parameter;
    grid: half_plane_holds_exactly_one_of_each_mirror_pair, mirror_negates_the_signed_frequency_except_on_nyquist_lines;
    kmeans: converged_clusters_hold_the_points_nearest_their_means, indexed_nearest_centroid_matches_the_direct_search, kmeans_is_deterministic_for_any_thread_count, few_points_each_get_their_own_cluster, tables_partition_the_points;
    shrink: bessel_j0_matches_its_integral_representation, bessel_j0_vanishes_at_its_tabulated_zeros, gauss_legendre_integrates_polynomials_exactly, window_spectrum_matches_a_direct_hankel_sum, window_spectral_energy_equals_its_spatial_energy, shrink_unit_holds_the_requested_share_of_energy;
    spectrum_fit: groups_carry_equal_energy_and_the_whole, tables_list_frequencies_in_proportion_to_power, faint_bins_keep_their_share_together, capped_budgets_give_freed_cosines_to_the_other_strata, capped_budgets_fill_water_levels, resolving_width_spans_the_periods_of_the_low_quartile, the_welch_operator_is_welchs_estimate_of_grid_cosines, sharpening_inverts_welchs_estimate_and_keeps_the_total;
    stratify: strata_energies_are_equal_within_one_mirror_pair, strata_are_disjoint_symmetric_and_cover_every_bin_with_power, higher_strata_hold_higher_powers, a_single_peak_leaves_empty_strata, budget_sums_to_j_with_the_remainder_on_the_highest_energies, window_width_follows_section_4_3_and_is_clamped, invalid_spectra_are_rejected_with_their_position, log_power_strata_bound_the_power_ratio_within_each_stratum;
    texture: subdivision_starts_with_one_block_and_refines_only_when_needed, false_colours_are_counted_exactly, jacobi_diagonalises_a_symmetric_matrix, region_holds_the_requested_share_of_energy, options_are_validated;
}

/// Every `pub fn` of a `pub mod tests` under `src/` is run above, and nothing else is.
#[test]
fn every_unit_test_is_run() {
    let mut bodies = Vec::new();
    let mut stack = vec![std::path::PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/src"
    ))];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).unwrap();
                if let Some((_, tests)) = text.split_once("\npub mod tests {") {
                    bodies.extend(tests.lines().filter_map(|l| {
                        let name = l.strip_prefix("    pub fn ")?;
                        Some(name[..name.find('(')?].to_owned())
                    }));
                }
            }
        }
    }
    bodies.sort();
    let mut run: Vec<String> = RUN.iter().map(|s| (*s).to_owned()).collect();
    run.sort();
    assert_eq!(
        bodies, run,
        "unit-test bodies under src/ against the tests run here"
    );
}
