//! The crate's unit tests: their bodies are `pub mod tests` in the source modules, behind the
//! `unit-tests` feature, run here (see `spectex_testkit::unit`).

spectex_testkit::unit_tests! {
    spectex_gpu;
    axis: cell_axis_splits_cells_and_rejects_out_of_range, cell_range_covers_the_pixels_and_their_displacements, cell_range_of_a_displacement_range_holds_every_pixel, cell_axis_matches_its_wgsl_twin;
    combine: passes_of_every_operation_validate, exact_arithmetic_rounds_as_the_cpu, combination_passes_are_apply_bit_for_bit;
    classic: records_match_the_wgsl, shape_constants_are_the_shaders_overrides, specialised_pipelines_render_the_generic_bits, skew_parts_add_up_to_the_skewed_coordinate, params_and_octaves_carry_the_model, halving_needs_every_lattice_halved_exactly;
    evaluator: reserve_makes_what_the_render_uses;
    gabor: params_match_the_wgsl, drawn_cells_render_the_per_pixel_bits;
    islamic: params_match_the_wgsl, fixed_point_sums_are_the_fraction_of_a_times_n,
        uniform_segments_hold_the_table_or_name_the_limit;
    lrp: records_match_the_wgsl, lattice_offsets_are_the_rounded_f64_differences, pack_concatenates_tables_in_order, an_unknown_constant_table_is_refused,
        boxes_hold_every_reached_point_within_the_budget, drawn_points_render_the_per_pixel_bits;
    matrix: params_match_the_wgsl;
    tiling: params_match_the_wgsl;
    phasor: records_match_the_wgsl, nested_blends_are_unsupported_in_phasor_models, binned_masks_render_the_unbinned_bits;
    pipeline: warp_params_match_the_wgsl;
    render: pack_params_match_the_wgsl, copied_tiles_land_where_their_rows_say, packing_is_the_cpus_quantisation_and_counts_what_it_clamps, store_shaders_validate_with_the_record_layout;
    shaders: model_shaders_use_every_binding_in_the_host_order, names_are_unique_and_composition_prepends_common;
    simulate: sim_params_match_the_wgsl;
    subdivision: params_match_the_wgsl;
    texton: params_match_the_wgsl, drawn_cells_render_the_per_pixel_bits;
    texture: records_match_the_wgsl;
    voronoi: params_match_the_wgsl;
    wavelet: records_match_the_wgsl;
    warp: compose_params_match_the_wgsl, ordered_words_decode_to_their_values, displacement_range_is_the_exact_extremes, a_displacement_kept_on_the_device_is_the_host_composition;
    export_emitter: whole_sides_are_integers_up_to_2_pow_24, lattice_tables_decompose_every_bit_weight,
        modular_split_is_exact_for_f32_sides;
    export_wgsl_text: members_naga_would_rename_get_a_letter_suffix_everywhere, rename_skips_members_fields_and_comments, rename_turns_buffer_tables_into_accessor_calls, strip_removes_bindings_and_entry_points;
}
