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
                        spectex_gpu::unit_tests::$module::$test();
                    }
                )+
            }
        )+
        const RUN: &[&str] = &[$($(stringify!($test)),+),+];
    };
}

unit_tests! {
    axis: cell_axis_splits_cells_and_rejects_out_of_range, cell_range_covers_the_pixels_and_their_displacements, cell_axis_matches_its_wgsl_twin;
    classic: records_match_the_wgsl, skew_parts_add_up_to_the_skewed_coordinate, params_and_octaves_carry_the_model, halving_needs_every_lattice_halved_exactly;
    gabor: params_match_the_wgsl;
    islamic: params_match_the_wgsl, fixed_point_sums_are_the_fraction_of_a_times_n;
    lrp: records_match_the_wgsl, lattice_offsets_are_the_rounded_f64_differences, pack_concatenates_tables_in_order;
    matrix: params_match_the_wgsl;
    phasor: records_match_the_wgsl, nested_blends_are_unsupported_in_phasor_models;
    pipeline: warp_params_match_the_wgsl;
    render: pack_params_match_the_wgsl, store_shaders_validate_with_the_record_layout;
    shaders: model_shaders_use_every_binding_in_the_host_order, names_are_unique_and_composition_prepends_common;
    simulate: sim_params_match_the_wgsl;
    subdivision: params_match_the_wgsl;
    texton: params_match_the_wgsl;
    texture: records_match_the_wgsl;
    voronoi: params_match_the_wgsl;
    wavelet: records_match_the_wgsl;
    export_emitter: whole_sides_are_integers_up_to_2_pow_24, lattice_tables_decompose_every_bit_weight;
    export_wgsl_text: members_naga_would_rename_get_a_letter_suffix_everywhere, rename_skips_members_fields_and_comments, rename_turns_buffer_tables_into_accessor_calls, strip_removes_bindings_and_entry_points;
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
