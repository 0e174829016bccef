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
                        spectex_model::unit_tests::$module::$test();
                    }
                )+
            }
        )+
        const RUN: &[&str] = &[$($(stringify!($test)),+),+];
    };
}

unit_tests! {
    classic: gradient_dot_is_perlins_grad, fade_and_lattice_values_hit_their_ends, poisson_cdf_matches_the_pmf_sum, validation_names_the_field, json_round_trip_and_unknown_fields, worley_needs_the_last_non_zero_coefficient;
    combine: operations_follow_their_definitions, lookup_and_ramp_interpolate_and_clamp, histogram_matching_maps_quantiles, validation_names_nested_fields;
    error: a_bound_is_met_by_the_f32_nearest_it;
    file: a_file_records_the_fit_that_made_it;
    filter: pure_cosines_in_band_get_the_box_attenuation, nothing_survives_past_the_fade, the_gain_is_continuous_and_falls_with_the_footprint, gain_table_matches_the_quadrature, filtered_square_keeps_the_mean_and_converges, spread_gain_matches_a_direct_average, profile_series_converge_to_their_profiles;
    fixtures: budgets_are_spread_and_models_valid;
    gabor: unit_std_dev_matches_a_polar_integration, unit_std_dev_at_zero_frequency_has_a_closed_form;
    grid: tiles_evaluate_the_same_positions, validation_names_the_parameter, footprint_is_the_pixel_box_only_when_minified, locate_cell_splits_exactly_and_rejects_out_of_range;
    islamic: defaults_validate, validation_names_the_field_and_range, the_tilings_are_edge_to_edge_and_cover_the_cell, the_square_contact_points_are_the_closed_form, tables_stay_within_their_bounds, the_lattice_map_is_the_inverse_of_the_basis;
    kind: kind_names_are_the_model_file_tags, each_kind_lives_in_the_module_of_its_name;
    math: fract_turns_is_exact, cos_turns_matches_f64_cos, window_matches_the_model_definition, window_is_one_at_the_centre, exp_poly_matches_f64_exp, exp_poly_reduction_constants_and_clamping, atan2_turns_matches_f64;
    matrix: lucas_and_fibonacci_numbers, inverse_times_matrix_is_the_identity, invalid_matrices_are_refused_by_field, json_round_trip;
    period: reduce_is_exact_and_one_period_apart_agrees, wrap_and_cells, parse_and_range;
    phasor: valid_model_and_named_errors, fields_repeat_with_periods_their_repeat_divides, image_field_interpolates_and_wraps, radius_and_density;
    phasor_kernels: two_lobes_switch_sign_beyond_a_right_angle, gradient_orientation_follows_the_image, layers_are_independent_in_3d_only;
    random: hash_matches_independent_reference, prng_stream_matches_independent_reference, permute_is_a_bijection_on_a_window, uniform_floats_are_in_range_and_exact, neighbouring_cells_are_uniform, hash_avalanche, hoisted_keys_compose_to_the_cell_hash, seeds_layers_and_axes_decorrelate;
    simulation: bs_rules_parse_and_bad_ones_name_the_field, out_of_range_fields_are_named, files_round_trip_and_check_their_version, pearson_rates_per_pixel;
    subdivision: byte_sum_has_mean_zero_and_variance_21845, catmull_rom_at_a_half_is_the_four_point_stencil, the_window_covers_every_tap_of_the_next_level, normalise_names_one_point_once, validation_names_the_field;
    target: fractal_power_follows_eq_8;
    texton: defaults_validate_and_reach_one_cell, validation_names_the_field_and_range, poisson_counts_follow_the_pmf, ellipsoid_height_and_support, bilinear_reproduces_texels_and_interpolates;
    texture: mean_mipmap_averages_aligned_groups, filtered_structure_fades_to_the_mean, block_weights_are_a_partition_of_unity, one_block_is_a_fourier_series_of_the_period, placement_cross_fade_keeps_unit_energy_and_is_continuous, without_placement_the_structure_is_periodic, validation_names_the_field_and_range;
    voronoi: defaults_validate, validation_names_the_field_and_range, three_dimensions_validate_with_field_paths, a_file_without_dimensions_is_2d_and_2d_files_are_unchanged, the_3d_draw_follows_the_contract, the_pruned_3d_search_is_the_full_search, the_centroid_of_a_regular_grid_cell_is_its_seed, clipped_centroids_match_dense_sampling, relaxation_stays_in_the_cells_and_evens_the_spacing;
    warp: displacement_is_clamped_and_nan_free, validation_names_the_nested_field, depth_is_limited, x_and_y_must_be_grey, windows_keep_displaced_positions_in_range, json_round_trip_and_unknown_fields;
    wavelet: band_pass_tile_matches_a_dense_matrix_reference, spatial_variance_matches_the_double_sum, spline_weights_partition_unity_and_hit_the_knots, bands_are_normalised_and_offsets_drawn_by_the_contract, validation_names_the_field, json_round_trip_and_unknown_fields, tile_has_unit_spatial_variance_and_is_deterministic;
    window: bessel_matches_a_long_direct_sum, window_integral_matches_the_paper, lattice_envelope_varies_less_than_five_percent, variance_envelope_is_not_flat, window_bandwidth_matches_a_cartesian_estimate, window_shape;
    warp_builder: defaults_are_the_documented_constants, given_models_are_kept, invalid_settings_name_the_field;
    classic_builder: defaults_are_the_documented_constants, levels_follow_basis_and_sum_unless_given, setters_reach_every_field_in_any_order, invalid_settings_name_the_field;
    texton_builder: defaults_are_the_documented_constants, invalid_settings_name_the_field;
    voronoi_builder: defaults_are_the_documented_constants, invalid_settings_name_the_field;
    wavelet_builder: defaults_are_the_documented_constants, invalid_settings_name_the_field;
    phasor_builder: defaults_are_the_documented_constants, levels_show_every_output_in_the_unit_interval, invalid_settings_name_the_field;
    gabor_builder: defaults_are_the_documented_constants, amplitude_and_std_dev_replace_each_other, invalid_settings_name_the_field;
    subdivision_builder: defaults_are_the_documented_constants, invalid_settings_name_the_field;
    matrix_builder: defaults_are_the_documented_constants, invalid_settings_name_the_field;
    combine_builder: defaults_are_the_documented_constants, invalid_settings_name_the_field;
    islamic_builder: defaults_are_the_documented_constants, invalid_settings_name_the_field;
    lrp_builder: defaults_and_strata_in_order, invalid_settings_name_the_field;
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
