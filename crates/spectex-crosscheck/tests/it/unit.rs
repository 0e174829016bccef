//! The crate's unit tests: their bodies are `pub mod tests` in the source modules, behind the
//! `unit-tests` feature, run here (see `spectex_testkit::unit`).

spectex_testkit::unit_tests! {
    spectex_crosscheck;
    compare: planes_take_one_component_of_interleaved_values, identical_renders_measure_zero, one_outlier_sets_the_max_not_the_percentile, verdicts_follow_the_expected_failure_table;
    report: a_failure_writes_three_images_and_two_reports;
    tolerance_classic: classic_slope_bounds_hold_on_fine_renders, a_3d_noise_is_checked_off_its_lattice_planes, simplex_bounds_cover_a_scan_of_the_kernel, classic_bounds_follow_their_derivation;
    tolerance_combine: a_sum_adds_its_operands_bounds_and_a_maximum_takes_the_largest, crossed_waves_are_judged_by_their_operands_verdicts_and_the_operation, a_bounded_combination_keeps_the_generic_criterion, a_threshold_has_no_bound_and_a_smoothstep_scales_by_its_slope;
    tolerance_gabor: gabor_bound_grows_with_impulses, gabor_spectrum_bound_is_that_of_its_largest_frequency;
    tolerance_islamic: bounds_are_far_below_a_pixel;
    tolerance_lrp: kaiser_bessel_slope_is_plausible, lrp_bound_scales_with_amplitude_and_terms;
    tolerance: spectral_bound_is_attained_by_a_scaled_signal;
    tolerance_phasor: filtered_squares_are_judged_by_their_slope, a_located_varying_duty_judges_the_output, a_profile_may_flip_only_next_to_its_jump, phases_are_compared_on_the_circle_where_they_are_determined, the_complex_sum_is_held_to_its_bound;
    tolerance_subdivision: catmull_rom_derivative_weights_sum_to_at_most_three, the_bound_grows_with_levels_and_amplitude;
    tolerance_texton: the_sum_bound_grows_with_the_textons_and_the_maximum_does_not, the_ellipsoid_bound_is_the_square_root_of_the_rho2_error;
    tolerance_texture: texture_slope_bound_holds_on_a_fine_render, texture_bound_per_component;
    tolerance_voronoi: bounds_are_small_against_a_cell, the_verdict_excuses_only_ambiguous_pixels;
    tolerance_warp: warp_mean_counts_jumps_only_near_kernel_boundaries, warp_bound_grows_with_strength, a_warp_is_checked_on_its_base_plane, warp_of_a_model_without_regularity_has_no_tolerance;
    tolerance_wavelet: wavelet_slope_bounds_hold_on_fine_renders, wavelet_bound_follows_its_derivation;
}
