//! A combination's export (`shaders/export/combine.wgsl`): like a warp, a composition — each
//! operand is exported as its own prefixed model, and the glue's `combine_sample_cell`
//! (written here, per operation and channel) evaluates them at the position and applies
//! `CombineOp::apply`'s expression in WGSL (the compute path applies it on the host in f32).

use std::collections::HashSet;
use std::fmt::Write as _;

use spectex_model::combine::{CombineOp, RampStop};
use spectex_model::{Combine, ModelKind};

use super::{
    Emitter, ExportKind, ExportNode, export_shader, float, parts, rename, top_level_names,
};
use crate::GpuError;

impl ExportKind for Combine {
    const GLUE: &'static str = include_str!("../../../../shaders/export/combine.wgsl");

    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        Ok(ExportNode::Combine {
            op: self.op.clone(),
            operands: self
                .operands
                .iter()
                .map(|m| parts(m, z))
                .collect::<Result<_, _>>()?,
            channels: self.output_channels(),
        })
    }
}

/// Bytes of the constant tables a combination adds: a histogram's table, a ramp's stops
/// (their position and colour), or the one unused entry of each.
pub(super) fn table_bytes(op: &CombineOp) -> u64 {
    let (knots, stops) = tables(op);
    4 * knots.len() as u64 + 16 * stops.len() as u64
}

/// The histogram table (two zeros without one) and the ramp stops (one zero stop without).
fn tables(op: &CombineOp) -> (Vec<f32>, Vec<RampStop>) {
    let knots = match op {
        CombineOp::Histogram { table, .. } => table.clone(),
        _ => vec![0.0, 0.0],
    };
    let stops = match op {
        CombineOp::Ramp { stops } => stops.clone(),
        _ => vec![RampStop {
            at: 0.0,
            colour: [0.0; 3],
        }],
    };
    (knots, stops)
}

/// Channel `c` of operand `k`'s value `v<k>` (`width` channels).
fn channel(k: usize, width: usize, c: usize) -> String {
    if width == 1 {
        format!("v{k}")
    } else {
        format!("v{k}[{c}]")
    }
}

/// The WGSL expression of `op` for output channel `c` over the operands of `widths`
/// (`CombineOp::apply`, the same operations in the same order).
fn expression(op: &CombineOp, widths: &[usize], c: usize) -> String {
    let ch = |k: usize, c: usize| channel(k, widths[k], c);
    let fold = |f: &dyn Fn(String, String) -> String| {
        (1..widths.len()).fold(ch(0, c), |acc, k| f(acc, ch(k, c)))
    };
    match op {
        CombineOp::Add => fold(&|a, b| format!("({a} + {b})")),
        CombineOp::Multiply => fold(&|a, b| format!("({a} * {b})")),
        CombineOp::Min => fold(&|a, b| format!("min({a}, {b})")),
        CombineOp::Max => fold(&|a, b| format!("max({a}, {b})")),
        CombineOp::Mix => {
            let (a, b, t) = (ch(0, c), ch(1, c), ch(2, 0));
            format!("{a} + ({b} - {a}) * {t}")
        }
        CombineOp::Smoothstep { edges } => format!(
            "combine_smoothstep({}, {}, {})",
            float(edges[0]),
            float(edges[1]),
            ch(0, c)
        ),
        CombineOp::AbsFold {
            offset,
            step,
            folds,
        } => format!(
            "combine_abs_fold({}, {}, {}, {folds}u)",
            ch(0, c),
            float(*offset),
            float(*step)
        ),
        CombineOp::SinFold { gain } => format!("sin_turns({} * {})", float(*gain), ch(0, c)),
        CombineOp::Histogram { domain, .. } => format!(
            "combine_lookup({}, {}, {})",
            float(domain[0]),
            float(domain[1]),
            ch(0, c)
        ),
        CombineOp::Ramp { .. } => format!("combine_ramp({}, {c}u)", ch(0, 0)),
    }
}

impl Emitter<'_> {
    /// Emits a combination's operands (each its own model), then its glue and
    /// `combine_sample_cell` under its own prefix; returns that function's name.
    pub(super) fn combine(
        &mut self,
        op: &CombineOp,
        operands: &[ExportNode],
        channels: usize,
        ret: &str,
        out: &mut String,
    ) -> Result<String, GpuError> {
        let mut names = Vec::new();
        let mut widths = Vec::new();
        for node in operands {
            let width = node.channels();
            let value = if width == 1 { "f32" } else { "vec3<f32>" };
            names.push(self.node(node, value, out)?);
            widths.push(width);
        }
        let k = self.models;
        self.models += 1;
        self.sources.push(format!(
            "model {k}: a combination (glue shaders/export/combine.wgsl) of the models before it"
        ));
        let prefix = format!("spectex_m{k}_");
        let (knots, stops) = tables(op);
        self.constant_bytes += table_bytes(op) as usize;
        let mut code = export_shader("combine");
        let _ = write!(
            code,
            "\nconst combine_knots: u32 = {n}u;\n\
             var<private> combine_table: array<f32, {n}> = array<f32, {n}>({});\n\
             const combine_stops: u32 = {s}u;\n\
             var<private> combine_stops_at: array<f32, {s}> = array<f32, {s}>({});\n\
             var<private> combine_stops_colour: array<vec3<f32>, {s}> = \
             array<vec3<f32>, {s}>({});\n",
            knots
                .iter()
                .map(|v| float(*v))
                .collect::<Vec<_>>()
                .join(", "),
            stops
                .iter()
                .map(|s| float(s.at))
                .collect::<Vec<_>>()
                .join(", "),
            stops
                .iter()
                .map(|s| format!(
                    "vec3<f32>({}, {}, {})",
                    float(s.colour[0]),
                    float(s.colour[1]),
                    float(s.colour[2])
                ))
                .collect::<Vec<_>>()
                .join(", "),
            n = knots.len(),
            s = stops.len(),
        );
        let _ = write!(
            code,
            "\n/// The combination at the position `cell + offset` (pixels): its operands there, \
             then the operation per channel.\n\
             fn combine_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> {ret} {{\n"
        );
        for (k, name) in names.iter().enumerate() {
            let _ = writeln!(code, "    let v{k} = {name}(cell, offset);");
        }
        let exprs: Vec<String> = (0..channels).map(|c| expression(op, &widths, c)).collect();
        if channels == 1 {
            let _ = writeln!(code, "    return {};\n}}", exprs[0]);
        } else {
            let _ = writeln!(code, "    return {ret}({});\n}}", exprs.join(", "));
        }
        let mut map = self.common_map.clone();
        for name in top_level_names(&code) {
            map.insert(name.clone(), format!("{prefix}{name}"));
        }
        let _ = write!(
            out,
            "\n// ---- spectex: model {k}, a combination, prefix {prefix} ----\n"
        );
        out.push_str(&rename(&code, &map, &HashSet::new()));
        Ok(format!("{prefix}combine_sample_cell"))
    }
}
