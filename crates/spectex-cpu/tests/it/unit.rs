//! The crate's unit tests: their bodies are `pub mod tests` in the source modules, behind the
//! `unit-tests` feature, run here (see `spectex_testkit::unit`).

spectex_testkit::unit_tests! {
    spectex_cpu;
    classic_tables: gradient_terms_fold_gradient_dot_exactly, coded_gradient_dot_is_gradient_dot_exactly;
    gabor: poisson_chunk_keeps_products_normal, poisson_count_has_poisson_moments, count_is_capped_and_the_loop_bounded_for_nonsense_models, gaussian_exponent_is_the_truncation_log, locate_splits_cells_and_rejects_out_of_range, kept_impulses_follow_the_draw_order;
    islamic: the_signed_distance_matches_brute_force_in_f64, the_pattern_has_its_tilings_symmetries, the_band_is_the_box_filtered_coverage;
    texton: rows_match_the_per_pixel_definition, an_isolated_ellipsoid_has_its_radii;
    tiling: barycentric_weights_reproduce_the_position;
    combine: combinations_are_their_operation_of_the_operands_renders;
    voronoi: outputs_match_brute_force_over_all_nearby_seeds, outputs_3d_match_brute_force_near_and_far, the_3d_fast_path_is_the_full_search, a_regular_3d_lattice_slice_at_cell_centres_is_the_2d_diagram, a_periodic_3d_diagram_repeats_in_x_and_y_only, image_colours_are_the_texel_under_the_seed, a_regular_grid_has_known_distances;
}
