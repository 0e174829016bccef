//! End-to-end tests of the `spectex` binary: outputs on success, and on bad input one
//! `error: …` line, exit status 1 and no output file.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{s, scratch, spectex, spectex_ok, z_of};

/// Asserts the failure contract ([`crate::bad_inputs::failure_contract`]).
fn assert_fails(out: &Output, dir: &Path, needles: &[&str]) {
    if let Err(wrong) = crate::bad_inputs::failure_contract(out, dir, needles) {
        panic!("{wrong}");
    }
}

fn write_png(path: &Path, w: u32, h: u32) {
    spectex_testkit::image_files::save(
        &image::DynamicImage::from(image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb([(x * 7) as u8, (y * 3) as u8, ((x + y) * 5) as u8])
        })),
        path,
    )
    .unwrap();
}

#[test]
fn rpn_on_the_built_in_exemplar() {
    let dir = scratch("default");
    let out = dir.join("out.png");
    let o = spectex(&["rpn", "-o", s(&out)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = spectex_testkit::image_files::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (256, 256));
    assert!(img.color().has_color());
    // Only the output is there: the temporary file was renamed, not copied.
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
}

#[test]
fn rpn_sizes_depths_formats_and_seeds() {
    let dir = scratch("formats");
    let input = dir.join("in.png");
    write_png(&input, 40, 30);
    let p16 = dir.join("a.png");
    let o = spectex(&[
        "rpn",
        s(&input),
        "-o",
        s(&p16),
        "--size",
        "100x64",
        "--seed",
        "9",
        "--bit-depth",
        "16",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = spectex_testkit::image_files::open(&p16).unwrap();
    assert_eq!((img.width(), img.height()), (100, 64));
    assert_eq!(img.color(), image::ColorType::Rgb16);

    // EXR keeps values exactly as f32: the mean of each channel equals the sample's.
    let exr = dir.join("a.exr");
    let o = spectex(&["rpn", s(&input), "-o", s(&exr), "--adsn", "--size", "64x64"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = spectex_testkit::image_files::open(&exr)
        .unwrap()
        .to_rgb32f();
    let sample = spectex_testkit::image_files::open(&input)
        .unwrap()
        .to_rgb32f();
    for c in 0..3 {
        let mean = |im: &image::Rgb32FImage| {
            im.pixels().map(|p| f64::from(p.0[c])).sum::<f64>()
                / f64::from(im.width() * im.height())
        };
        assert!((mean(&out) - mean(&sample)).abs() < 1e-5, "channel {c}");
    }

    // Same seed, same bytes; the output is a pure function of input and seed.
    let (x, y) = (dir.join("x.png"), dir.join("y.png"));
    assert!(
        spectex(&["rpn", s(&input), "-o", s(&x), "--seed", "5"])
            .status
            .success()
    );
    assert!(
        spectex(&["rpn", s(&input), "-o", s(&y), "--seed", "5"])
            .status
            .success()
    );
    assert_eq!(std::fs::read(&x).unwrap(), std::fs::read(&y).unwrap());
}

#[test]
fn grey_and_alpha_inputs() {
    let dir = scratch("grey");
    let grey = dir.join("g.png");
    spectex_testkit::image_files::save(
        &image::DynamicImage::from(image::GrayImage::from_fn(20, 20, |x, y| {
            image::Luma([((x * y) % 256) as u8])
        })),
        &grey,
    )
    .unwrap();
    let out = dir.join("g-out.png");
    assert!(spectex(&["rpn", s(&grey), "-o", s(&out)]).status.success());
    assert_eq!(
        spectex_testkit::image_files::open(&out).unwrap().color(),
        image::ColorType::L8
    );

    let rgba = dir.join("a.png");
    spectex_testkit::image_files::save(
        &image::DynamicImage::from(image::RgbaImage::from_fn(20, 20, |x, y| {
            image::Rgba([x as u8 * 9, y as u8 * 9, 100, 128])
        })),
        &rgba,
    )
    .unwrap();
    let out = dir.join("a-out.png");
    let o = spectex(&["rpn", s(&rgba), "-o", s(&out)]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("alpha channel"));
    assert_eq!(
        spectex_testkit::image_files::open(&out).unwrap().color(),
        image::ColorType::Rgb8
    );
}

#[test]
fn analyze_writes_every_file() {
    let dir = scratch("analyze");
    let out = dir.join("analysis");
    let o = spectex(&["analyze", "-o", s(&out)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in [
        "periodic.png",
        "smooth.png",
        "log_spectrum.png",
        "log_spectrum_periodic.png",
        "welch_psd.png",
        "variance_spectrum.png",
        "radial_profile.csv",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let csv = std::fs::read_to_string(out.join("radial_profile.csv")).unwrap();
    assert!(csv.starts_with("radius_cycles_per_pixel,count,red,green,blue,luminance\n"));
    // Welch block for the 256² exemplar is 128²: every one of its frequencies is counted once.
    let counted: usize = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse::<usize>().unwrap())
        .sum();
    assert_eq!(counted, 128 * 128);
    let psd = spectex_testkit::image_files::open(out.join("welch_psd.png")).unwrap();
    assert_eq!((psd.width(), psd.height()), (128, 128));

    let exr = dir.join("exr");
    assert!(
        spectex(&["analyze", "-o", s(&exr), "--format", "exr"])
            .status
            .success()
    );
    assert!(exr.join("welch_psd.exr").is_file());
}

#[test]
fn unwritable_output_directory() {
    // Root ignores permission bits, so only run the check where they bite.
    let dir = scratch("readonly");
    let ro = dir.join("ro");
    std::fs::create_dir(&ro).unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
        if std::fs::write(ro.join("probe"), b"x").is_ok() {
            eprintln!("skipping the read-only check: running as a user that ignores permissions");
            std::fs::remove_file(ro.join("probe")).unwrap();
            return;
        }
        let out = spectex(&["rpn", "-o", s(&ro.join("out.png"))]);
        assert_fails(&out, &ro, &["cannot write into"]);
    }
}

#[test]
fn help_has_examples() {
    for cmd in [&["--help"][..], &["rpn", "--help"], &["analyze", "--help"]] {
        let o = spectex(cmd);
        assert!(o.status.success());
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains("Examples:"), "{cmd:?}: {text}");
    }
}

#[test]
fn fit_render_synth_and_noise_end_to_end() {
    let dir = scratch("procedural");
    let model = dir.join("model.json");
    spectex_ok(&["fit", "-o", s(&model), "--budget", "8", "--strata", "2"]);
    let text = std::fs::read_to_string(&model).unwrap();
    let parsed = spectex_model::from_json(&text).unwrap();
    // The built-in exemplar is in colour: a colour texture of three PCA channels, each with
    // the whole budget in random-phase strata (no --structure).
    let spectex_model::Model::Texture(tex) = &parsed else {
        panic!("fit wrote {parsed:?}")
    };
    assert_eq!(tex.channels.len(), 3);
    assert!(tex.colour.is_some());
    for ch in &tex.channels {
        let budget: usize = ch.strata.iter().map(spectex_model::Stratum::cosines).sum();
        assert_eq!(budget, 8);
        assert!(ch.structure.is_none());
    }

    // Far away and scaled: a valid image of the asked size, on the CPU.
    let far = dir.join("far.exr");
    let out = spectex_ok(&[
        "render",
        s(&model),
        "-o",
        s(&far),
        "--size",
        "48x32",
        "--offset",
        "1e7,1e7",
        "--scale",
        "0.5",
        "--device",
        "cpu",
    ]);
    let img = spectex_testkit::image_files::open(&far).unwrap();
    assert_eq!((img.width(), img.height()), (48, 32));
    assert!(String::from_utf8_lossy(&out.stdout).contains("on the CPU"));

    // Auto renders on whatever exists and says which.
    let auto = dir.join("auto.png");
    let out = spectex_ok(&[
        "render",
        s(&model),
        "-o",
        s(&auto),
        "--size",
        "32x32",
        "--device",
        "auto",
    ]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("on the "));

    let synth = dir.join("synth.png");
    spectex_ok(&["synth", "-o", s(&synth), "--budget", "4", "--size", "40x40"]);
    assert_eq!(
        spectex_testkit::image_files::open(&synth).unwrap().width(),
        40
    );

    for kind in ["ring", "lobe", "band", "gabor"] {
        let png = dir.join(format!("{kind}.png"));
        let json = dir.join(format!("{kind}.json"));
        spectex_ok(&[
            "noise",
            kind,
            "-o",
            s(&png),
            "--size",
            "32x32",
            "--model",
            s(&json),
        ]);
        spectex_model::from_json(&std::fs::read_to_string(&json).unwrap()).unwrap();
    }
}

#[test]
fn texture_by_example_end_to_end() {
    let dir = scratch("texture");
    // A grey exemplar with structure: bricks-like stripes plus a ramp of noise.
    let grey = dir.join("grey.png");
    spectex_testkit::image_files::save(
        &image::DynamicImage::from(image::GrayImage::from_fn(96, 80, |x, y| {
            let stripe = if (y / 8 + (x / 24) % 2) % 2 == 0 {
                60
            } else {
                190
            };
            image::Luma([(stripe + ((x * 37 + y * 91) % 29)) as u8])
        })),
        &grey,
    )
    .unwrap();
    let model = dir.join("tex.json");
    spectex_ok(&[
        "fit",
        s(&grey),
        "-o",
        s(&model),
        "--budget",
        "20",
        "--structure",
        "0.3",
        "--turbulence",
        "2",
        "--random-placement",
    ]);
    let parsed = spectex_model::from_json(&std::fs::read_to_string(&model).unwrap()).unwrap();
    let spectex_model::Model::Texture(tex) = &parsed else {
        panic!("fit wrote {parsed:?}")
    };
    assert_eq!(tex.channels.len(), 1);
    assert!(tex.random_placement && tex.turbulence.is_some());
    let structure = tex.channels[0].structure.as_ref().unwrap();
    // J_R = round(0.3 · 20) = 6 cosines per block at most; the strata get the other 14.
    assert!(structure.cosines.iter().all(|b| b.len() <= 6));
    let strata: usize = tex.channels[0]
        .strata
        .iter()
        .map(spectex_model::Stratum::cosines)
        .sum();
    assert_eq!(strata, 14);
    let png = dir.join("tex.png");
    spectex_ok(&["render", s(&model), "-o", s(&png), "--size", "64x48"]);
    let img = spectex_testkit::image_files::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (64, 48));
    assert!(!img.color().has_color());

    // Colour in, colour out; synth takes the same options.
    let colour = dir.join("colour.png");
    write_png(&colour, 64, 64);
    let synth = dir.join("synth.png");
    spectex_ok(&[
        "synth",
        s(&colour),
        "-o",
        s(&synth),
        "--structure",
        "0.2",
        "--size",
        "40x30",
    ]);
    let img = spectex_testkit::image_files::open(&synth).unwrap();
    assert_eq!((img.width(), img.height()), (40, 30));
    assert!(img.color().has_color());

    // A contact sheet: exemplar + 4 panels of 32 px with 6 px gaps.
    let sheets = dir.join("sheets");
    let out = spectex_ok(&[
        "sheet",
        s(&grey),
        "-o",
        s(&sheets),
        "--panel",
        "32",
        "--budget",
        "10",
    ]);
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("| grey | 0.35 |"), "{table}");
    let sheet = spectex_testkit::image_files::open(sheets.join("grey_sheet.png")).unwrap();
    assert_eq!((sheet.width(), sheet.height()), (5 * 32 + 4 * 6, 32));
}

#[test]
fn relight_and_normal_maps() {
    let dir = scratch("relight");
    // A ramp rising to the right: under a light from the right (azimuth 0) at 45° the plane
    // z = 0.5·x has n·l = (−0.5·cos45° + sin45°)/√1.25 everywhere, with no ambient.
    let height = dir.join("ramp.png");
    spectex_testkit::image_files::save(
        &image::DynamicImage::from(image::ImageBuffer::<image::Luma<u16>, _>::from_fn(
            64,
            16,
            |x, _| image::Luma([(x * 1024) as u16]),
        )),
        &height,
    )
    .unwrap();
    // One pixel step is 1024/65535 of full scale; strength makes it 0.5 px.
    let strength = format!("{}", 0.5 * 65535.0 / 1024.0);
    let lit = dir.join("lit.exr");
    spectex_ok(&[
        "relight",
        s(&height),
        "-o",
        s(&lit),
        "--light",
        "0,45",
        "--ambient",
        "0",
        "--strength",
        &strength,
    ]);
    let img = common::read_exr(&lit);
    assert_eq!(img.names(), ["Y"], "a grey EXR is one Y channel");
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let want = (-0.5 * h + h) / 1.25f64.sqrt();
    let got = f64::from(img.channel("Y")[8 * img.data.2 + 30]);
    assert!((got - want).abs() < 1e-5, "{got} vs {want}");

    let normals = dir.join("normals.png");
    spectex_ok(&[
        "relight",
        s(&height),
        "-o",
        s(&normals),
        "--normals",
        "--periodic",
    ]);
    let n = spectex_testkit::image_files::open(&normals)
        .unwrap()
        .to_rgb8();
    assert_eq!(n.dimensions(), (64, 16));
    // Interior: leaning to −x (red below 128), no y component (green 128), z up (blue > 128).
    let p = n.get_pixel(30, 8).0;
    assert!(
        p[0] < 128 && (127..=128).contains(&p[1]) && p[2] > 128,
        "{p:?}"
    );
}

/// `spectex phasor` from flags (with a model file, control images and every output kind),
/// `render` of the written model giving the same image, and `slices` writing ordered layers
/// and their index.
#[test]
fn phasor_and_slices_end_to_end() {
    let dir = scratch("phasor");
    let control = dir.join("control.png");
    write_png(&control, 32, 16);
    let (img, model) = (dir.join("pwm.png"), dir.join("pwm.json"));
    spectex_ok(&[
        "phasor",
        "-o",
        s(&img),
        "--size",
        "96x64",
        "--profile",
        "square",
        "--duty-image",
        s(&control),
        "--orientation-image",
        s(&control),
        "--frequency-image",
        s(&control),
        "--bandwidth-image",
        s(&control),
        "--model",
        s(&model),
    ]);
    let again = dir.join("again.png");
    spectex_ok(&["render", s(&model), "-o", s(&again), "--size", "96x64"]);
    assert_eq!(
        std::fs::read(&img).unwrap(),
        std::fs::read(&again).unwrap(),
        "render of the model file differs from phasor's own output"
    );
    let pwm = spectex_testkit::image_files::open(&img).unwrap().to_luma8();
    assert!(
        pwm.pixels().all(|p| p[0] == 0 || p[0] == 255),
        "PWM not binary"
    );

    for kind in ["phase", "intensity", "gabor", "profiled"] {
        let p = dir.join(format!("{kind}.png"));
        spectex_ok(&[
            "phasor",
            "-o",
            s(&p),
            "--size",
            "40x30",
            "--coherent",
            "--output-kind",
            kind,
            "--harmonics",
            "1:1,3:0.33:90",
        ]);
    }

    let slab = dir.join("slab.json");
    spectex_ok(&[
        "phasor",
        "-o",
        s(&dir.join("slab.png")),
        "--three-d",
        "--isotropic",
        "--size",
        "32x32",
        "--model",
        s(&slab),
    ]);
    let layers = dir.join("layers");
    spectex_ok(&[
        "slices",
        s(&slab),
        "--z-range",
        "-4,4",
        "--layers",
        "3",
        "-o",
        s(&layers),
        "--size",
        "32x32",
    ]);
    let index = std::fs::read_to_string(layers.join("layers.csv")).unwrap();
    assert_eq!(
        index,
        "layer,z,file\n0,-4,layer_00000.png\n1,0,layer_00001.png\n2,4,layer_00002.png\n"
    );
    // The middle layer is the plane z = 0, which `phasor --z 0` rendered.
    assert_eq!(
        std::fs::read(layers.join("layer_00001.png")).unwrap(),
        std::fs::read(dir.join("slab.png")).unwrap()
    );
    assert_ne!(
        std::fs::read(layers.join("layer_00000.png")).unwrap(),
        std::fs::read(layers.join("layer_00002.png")).unwrap()
    );
}

/// The classic noises, wavelet noise and textons from `spectex noise`, at (1e7, −1e7) and on 3D planes, and
/// `spectex render` of the models they write gives the same bytes.
#[test]
fn classic_noises_end_to_end() {
    use image::GenericImageView;
    let dir = scratch("classic");
    let cases: &[(&str, &[&str])] = &[
        ("perlin", &[]),
        ("simplex", &["--dims", "3", "--z", "40.5"]),
        ("value", &["--dims", "3", "--z", "-3"]),
        ("fbm", &["--octaves", "4", "--sum", "ridged"]),
        (
            "fbm",
            &["--basis", "worley", "--poisson", "2", "--sum", "turbulence"],
        ),
        (
            "worley",
            &["--coefficients", "-1,1,0,0", "--metric", "manhattan"],
        ),
        ("wavelet", &[]),
        (
            "wavelet",
            &["--tile", "64", "--cell", "8", "--bands", "1,0.5,0.25"],
        ),
        (
            "wavelet",
            &[
                "--dims",
                "3",
                "--z",
                "40.5",
                "--bands",
                "1,-0.7",
                "--amplitude",
                "0.2",
            ],
        ),
        ("texton", &[]),
        (
            "texton",
            &[
                "--density",
                "2.5",
                "--spot",
                "gaussian",
                "--combine",
                "max",
                "--radii",
                "9,9",
            ],
        ),
    ];
    for (n, (kind, extra)) in cases.iter().enumerate() {
        let png = dir.join(format!("{n}-{kind}.png"));
        let model = dir.join(format!("{n}-{kind}.json"));
        let mut args = vec!["noise", kind, "-o", s(&png), "--model", s(&model)];
        args.extend(["--size", "64x48", "--offset", "1e7,-1e7", "--seed", "5"]);
        args.extend(extra.iter().copied());
        spectex_ok(&args);
        // `spectex render` on the written model gives the same image.
        let again = dir.join(format!("{n}-{kind}-again.png"));
        let z = z_of(extra);
        spectex_ok(&[
            "render",
            s(&model),
            "-o",
            s(&again),
            "--size",
            "64x48",
            "--offset",
            "1e7,-1e7",
            "--z",
            z,
        ]);
        let (a, b) = (
            spectex_testkit::image_files::open(&png).unwrap(),
            spectex_testkit::image_files::open(&again).unwrap(),
        );
        assert_eq!(a.dimensions(), (64, 48));
        assert_eq!(
            a.as_bytes(),
            b.as_bytes(),
            "{kind} {extra:?}: render differs from noise"
        );
        assert!(
            a.as_bytes().iter().any(|&v| v != a.as_bytes()[0]),
            "{kind} {extra:?}: constant image"
        );
    }
}

/// `spectex noise voronoi`, `combine`, `matrix`, `kensler` and `subdivision` with each output and operation: the
/// model they write renders to the same bytes, the image is not constant; bad flags fail
/// naming the field and the flag.
#[test]
fn voronoi_and_combinations_end_to_end() {
    use image::GenericImageView;
    let dir = scratch("survey-kinds");
    let cases: &[&[&str]] = &[
        &["voronoi"],
        &["voronoi", "--show", "f1"],
        &[
            "voronoi", "--show", "border", "--jitter", "0.9", "--lloyd", "2",
        ],
        &["voronoi", "--show", "f2-f1", "--cell", "12"],
        &[
            "voronoi", "--dims", "3", "--show", "border", "--jitter", "0.85",
        ],
        &[
            "voronoi",
            "--show",
            "palette",
            "--palette",
            "ff0000,00ff00,0000ff",
        ],
        &["combine"],
        &["combine", "multiply"],
        &["combine", "mix"],
        &["combine", "smoothstep", "--edges", "0.4,0.6"],
        &["combine", "fold", "--folds", "2"],
        &["combine", "sin-fold", "--gain", "3"],
        &["combine", "histogram"],
        &["combine", "ramp"],
        &["matrix"],
        &[
            "matrix",
            "--matrix",
            "3,0,0,7",
            "--iterations",
            "2",
            "--torus",
            "64",
        ],
        &["kensler"],
        &["kensler", "--dims", "3"],
        &["subdivision"],
        &[
            "subdivision",
            "--stencil",
            "cubic",
            "--hurst",
            "0.2",
            "--levels",
            "9",
        ],
    ];
    for (n, extra) in cases.iter().enumerate() {
        let png = dir.join(format!("{n}.png"));
        let model = dir.join(format!("{n}.json"));
        let mut args = vec!["noise"];
        args.extend(extra.iter().copied());
        args.extend(["-o", s(&png), "--model", s(&model), "--size", "64x48"]);
        spectex_ok(&args);
        let again = dir.join(format!("{n}-again.png"));
        spectex_ok(&["render", s(&model), "-o", s(&again), "--size", "64x48"]);
        let (a, b) = (
            spectex_testkit::image_files::open(&png).unwrap(),
            spectex_testkit::image_files::open(&again).unwrap(),
        );
        assert_eq!(a.dimensions(), (64, 48));
        assert_eq!(
            a.as_bytes(),
            b.as_bytes(),
            "{extra:?}: render differs from noise"
        );
        assert!(
            a.as_bytes().iter().any(|&v| v != a.as_bytes()[0]),
            "{extra:?}: constant image"
        );
    }
}

/// `spectex noise islamic` with its defaults (`-o OUT --size WxH` and nothing else) and with
/// each tiling, motif and output: the model it writes renders to the same bytes, the image is
/// not constant; bad flags fail naming the field, its range and the flag, leaving no file.
#[test]
fn islamic_patterns_end_to_end() {
    use image::GenericImageView;
    let dir = scratch("islamic");
    let plain = dir.join("plain.png");
    spectex_ok(&["noise", "islamic", "-o", s(&plain), "--size", "64x48"]);
    assert_eq!(
        spectex_testkit::image_files::open(&plain)
            .unwrap()
            .dimensions(),
        (64, 48)
    );
    let cases: &[&[&str]] = &[
        &["--tiling", "square", "--angle", "30", "--show", "filled"],
        &["--tiling", "hexagonal", "--star", "2", "--cell", "24"],
        &["--tiling", "4.8.8", "--star", "3", "--show", "filled"],
        &[
            "--tiling",
            "3.12.12",
            "--rotation",
            "-20",
            "--shift",
            "-3,5.5",
        ],
    ];
    for (n, extra) in cases.iter().enumerate() {
        let png = dir.join(format!("{n}.png"));
        let model = dir.join(format!("{n}.json"));
        let mut args = vec!["noise", "islamic"];
        args.extend(extra.iter().copied());
        args.extend(["-o", s(&png), "--model", s(&model), "--size", "64x48"]);
        spectex_ok(&args);
        let again = dir.join(format!("{n}-again.png"));
        spectex_ok(&["render", s(&model), "-o", s(&again), "--size", "64x48"]);
        let (a, b) = (
            spectex_testkit::image_files::open(&png).unwrap(),
            spectex_testkit::image_files::open(&again).unwrap(),
        );
        assert_eq!(
            a.as_bytes(),
            b.as_bytes(),
            "{extra:?}: render differs from noise"
        );
        assert!(
            a.as_bytes().iter().any(|&v| v != a.as_bytes()[0]),
            "{extra:?}: constant image"
        );
    }
}

/// `--device gpu` renders the classic noises (and `render MODEL --device gpu` their models)
/// within one 16-bit level of the CPU's image, saying it used the GPU. Skips with a printed
/// reason when no adapter exists, unless `SPECTEX_REQUIRE_GPU=1`.
#[test]
fn classic_noises_render_on_the_gpu() {
    if let Err(e) = spectex_gpu::GpuContext::new() {
        assert!(
            !std::env::var("SPECTEX_REQUIRE_GPU").is_ok_and(|v| v == "1"),
            "SPECTEX_REQUIRE_GPU=1 but no GPU: {e}"
        );
        eprintln!("SKIPPED classic_noises_render_on_the_gpu: {e}");
        return;
    }
    let dir = scratch("classic-gpu");
    let cases: &[(&str, &[&str])] = &[
        ("perlin", &[]),
        ("simplex", &["--dims", "3", "--z", "40.5"]),
        (
            "fbm",
            &["--basis", "value", "--octaves", "3", "--sum", "ridged"],
        ),
        (
            "worley",
            &[
                "--coefficients",
                "-1,1,0,0",
                "--metric",
                "manhattan",
                "--poisson",
                "2",
            ],
        ),
    ];
    for (n, (kind, extra)) in cases.iter().enumerate() {
        let model = dir.join(format!("{n}-{kind}.json"));
        let mut images = Vec::new();
        for device in ["cpu", "gpu"] {
            let png = dir.join(format!("{n}-{kind}-{device}.png"));
            let mut args = vec!["noise", kind, "-o", s(&png), "--model", s(&model)];
            args.extend(["--size", "48x32", "--offset", "1e7,-3e6", "--seed", "2"]);
            args.extend(["--bit-depth", "16", "--device", device]);
            args.extend(extra.iter().copied());
            let out = spectex_ok(&args);
            let stdout = String::from_utf8_lossy(&out.stdout);
            let want = if device == "gpu" {
                "on the GPU"
            } else {
                "on the CPU"
            };
            assert!(stdout.contains(want), "{kind}: {stdout}");
            images.push(
                spectex_testkit::image_files::open(&png)
                    .unwrap()
                    .into_luma16(),
            );
        }
        // `spectex render` of the written model on the GPU.
        let again = dir.join(format!("{n}-{kind}-render.png"));
        let z = z_of(extra);
        spectex_ok(&[
            "render",
            s(&model),
            "-o",
            s(&again),
            "--size",
            "48x32",
            "--offset",
            "1e7,-3e6",
            "--bit-depth",
            "16",
            "--z",
            z,
            "--device",
            "gpu",
        ]);
        images.push(
            spectex_testkit::image_files::open(&again)
                .unwrap()
                .into_luma16(),
        );
        assert_eq!(images[0].dimensions(), (48, 32));
        let cpu = images[0].as_raw();
        assert!(cpu.iter().any(|&v| v != cpu[0]), "{kind}: constant image");
        for other in &images[1..] {
            // The tolerances of spectex_crosscheck::tolerance::classic are below 1e-2 of a
            // level at these amplitudes, except at a 3D simplex seam (≤ 3.2e-3 ≈ 210 levels).
            let seam = if *kind == "simplex" { 210 } else { 1 };
            let worst = cpu
                .iter()
                .zip(other.as_raw())
                .map(|(a, b)| a.abs_diff(*b))
                .max()
                .unwrap();
            assert!(
                worst <= seam,
                "{kind}: GPU differs from CPU by {worst} levels"
            );
        }
    }
}

fn testdata_model(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../testdata/models/{name}.json"))
}

#[test]
fn warp_end_to_end() {
    use image::GenericImageView;
    let dir = scratch("warp");
    let (ring, gabor) = (
        testdata_model("lrp-ring"),
        testdata_model("gabor-isotropic"),
    );
    let cases: Vec<Vec<&str>> = vec![
        vec![],
        vec!["--base", s(&ring), "--by", s(&gabor), "--strength", "-12"],
        vec!["--base", s(&ring), "--by", s(&gabor), "--by-y", s(&ring)],
    ];
    let mut images = Vec::new();
    for (n, extra) in cases.iter().enumerate() {
        let png = dir.join(format!("{n}.png"));
        let model = dir.join(format!("{n}.json"));
        let mut args = vec!["noise", "warp", "-o", s(&png), "--model", s(&model)];
        args.extend(["--size", "48x32", "--offset", "1e7,-1e7"]);
        args.extend(extra.iter().copied());
        spectex_ok(&args);
        let again = dir.join(format!("{n}-again.png"));
        spectex_ok(&[
            "render",
            s(&model),
            "-o",
            s(&again),
            "--size",
            "48x32",
            "--offset",
            "1e7,-1e7",
        ]);
        let (a, b) = (
            spectex_testkit::image_files::open(&png).unwrap(),
            spectex_testkit::image_files::open(&again).unwrap(),
        );
        assert_eq!(a.dimensions(), (48, 32));
        assert_eq!(a.as_bytes(), b.as_bytes(), "{extra:?}: render differs");
        assert!(
            a.as_bytes().iter().any(|&v| v != a.as_bytes()[0]),
            "constant"
        );
        images.push(a.as_bytes().to_vec());
    }
    // The warp changes the base, and --by-y changes the warp.
    let base = dir.join("base.png");
    let out = spectex(&[
        "render",
        s(&ring),
        "-o",
        s(&base),
        "--size",
        "48x32",
        "--offset",
        "1e7,-1e7",
    ]);
    assert!(out.status.success());
    let base = spectex_testkit::image_files::open(&base).unwrap();
    assert_ne!(base.as_bytes(), &images[1][..]);
    assert_ne!(images[1], images[2]);
}

/// `--no-filter`: at `--scale 4` the default render fades what its pixels cannot resolve and
/// differs from the point-sampled one; at `--scale 1` both are the same bytes.
#[test]
fn no_filter_point_samples_minified_renders() {
    let dir = scratch("no-filter");
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/models/lrp-gravel.json");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec!["render", s(&model), "-o", s(&out), "--size", "32x24"];
        args.extend_from_slice(extra);
        spectex_ok(&args);
        std::fs::read(&out).unwrap()
    };
    let filtered = render("f4.png", &["--scale", "4"]);
    let point = render("p4.png", &["--scale", "4", "--no-filter"]);
    assert_ne!(filtered, point, "a minified render is filtered by default");
    let near = render("f1.png", &["--scale", "1"]);
    let near_point = render("p1.png", &["--scale", "1", "--no-filter"]);
    assert_eq!(near, near_point, "at scale 1 filtering changes nothing");
}

/// `noise voronoi|islamic|matrix|combine|kensler --periodic`: each 2P × 2P render (16-bit PNG,
/// at an offset) is its P × P quarter repeated, sample by sample; a period a kind cannot take
/// fails naming the field and the valid sides.
#[test]
fn periodic_noise_of_every_other_kind_tiles_seamlessly() {
    let dir = scratch("periodic-kinds");
    let runs: &[(&str, &[&str], u32)] = &[
        (
            "voronoi",
            &["noise", "voronoi", "--cell", "16", "--lloyd", "2"],
            64,
        ),
        (
            "voronoi-colour",
            &["noise", "voronoi", "--cell", "20", "--show", "palette"],
            80,
        ),
        ("islamic", &["noise", "islamic", "--cell", "32"], 64),
        ("matrix", &["noise", "matrix", "--torus", "32"], 64),
        ("combine", &["noise", "combine"], 128),
        ("kensler", &["noise", "kensler", "--cell", "16"], 64),
    ];
    for (name, args, p) in runs {
        let out = dir.join(format!("{name}.png"));
        let size = format!("{}x{}", 2 * p, 2 * p);
        let period = format!("{p}x{p}");
        let mut all = args.to_vec();
        all.extend([
            "-o",
            s(&out),
            "--size",
            &size,
            "--periodic",
            &period,
            "--offset",
            "-1003,517",
            "--bit-depth",
            "16",
        ]);
        spectex_ok(&all);
        let img = spectex_testkit::image_files::open(&out)
            .unwrap()
            .to_luma16();
        assert_eq!(img.dimensions(), (2 * p, 2 * p), "{name}");
        let mut distinct = std::collections::HashSet::new();
        for y in 0..2 * p {
            for x in 0..2 * p {
                distinct.insert(img.get_pixel(x, y)[0]);
                assert_eq!(
                    img.get_pixel(x, y),
                    img.get_pixel(x % p, y % p),
                    "{name}: pixel ({x}, {y})"
                );
            }
        }
        assert!(distinct.len() > 1, "{name}: a flat render");
        std::fs::remove_file(&out).unwrap();
    }
}

/// `--periodic`: a 2P × 2P render is its P × P quarter repeated (16-bit PNGs, compared sample
/// by sample), through `render` with a file's period and the flag, `noise fbm` and `synth`;
/// bad periods fail cleanly, naming the option and what is needed.
#[test]
fn periodic_renders_tile_seamlessly() {
    let dir = scratch("periodic");
    let quarters_equal = |path: &Path, p: u32| {
        let img = spectex_testkit::image_files::open(path)
            .unwrap()
            .to_luma16();
        assert_eq!(img.dimensions(), (2 * p, 2 * p), "{}", path.display());
        for y in 0..2 * p {
            for x in 0..2 * p {
                assert_eq!(
                    img.get_pixel(x, y),
                    img.get_pixel(x % p, y % p),
                    "{}: pixel ({x}, {y})",
                    path.display()
                );
            }
        }
    };
    let fbm = dir.join("fbm.png");
    spectex_ok(&[
        "noise",
        "fbm",
        "--cell",
        "32",
        "--octaves",
        "4",
        "-o",
        s(&fbm),
        "--size",
        "128x128",
        "--periodic",
        "64x64",
        "--offset",
        "-1000,37",
        "--bit-depth",
        "16",
    ]);
    quarters_equal(&fbm, 64);
    // Bare --periodic: the output's extent (--size × --scale), 64 × 64 model pixels here; the
    // same model rendered 128² with --periodic 64x64 is that render repeated.
    let ring = dir.join("ring.png");
    let ring_model = dir.join("ring.json");
    spectex_ok(&[
        "noise",
        "ring",
        "--radius",
        "0.0625",
        "--budget",
        "3",
        "-o",
        s(&ring),
        "--size",
        "64x64",
        "--periodic",
        "--bit-depth",
        "16",
        "--model",
        s(&ring_model),
    ]);
    let big = dir.join("big.png");
    spectex_ok(&[
        "render",
        s(&ring_model),
        "-o",
        s(&big),
        "--size",
        "128x128",
        "--periodic",
        "64x64",
        "--bit-depth",
        "16",
    ]);
    quarters_equal(&big, 64);
    let (tile, whole) = (
        spectex_testkit::image_files::open(&ring)
            .unwrap()
            .to_luma16(),
        spectex_testkit::image_files::open(&big)
            .unwrap()
            .to_luma16(),
    );
    for (x, y, v) in tile.enumerate_pixels() {
        assert_eq!(
            v,
            whole.get_pixel(x + 64, y + 64),
            "bare --periodic: pixel ({x}, {y})"
        );
    }
    // `render` at 10⁷ periods away (period 50 × 50).
    let far = dir.join("far.png");
    spectex_ok(&[
        "render",
        s(&ring_model),
        "-o",
        s(&far),
        "--size",
        "100x100",
        "--periodic",
        "50x50",
        "--offset",
        "5e8,-5e8",
        "--bit-depth",
        "16",
    ]);
    quarters_equal(&far, 50);
    // A model file recording a period: `render` uses it.
    let text = std::fs::read_to_string(&ring_model).unwrap();
    let with_period = text.replacen("\"model\"", "\"period\": [40, 40],\n  \"model\"", 1);
    let periodic_model = dir.join("ring-periodic.json");
    std::fs::write(&periodic_model, with_period).unwrap();
    let from_file = dir.join("from-file.png");
    spectex_ok(&[
        "render",
        s(&periodic_model),
        "-o",
        s(&from_file),
        "--size",
        "80x80",
        "--bit-depth",
        "16",
    ]);
    quarters_equal(&from_file, 40);
    // Phasor noise (constant fields): its kernel cells fitted to the period (48.8 → 42.7 px).
    let phasor = dir.join("phasor.png");
    spectex_ok(&[
        "phasor",
        "-o",
        s(&phasor),
        "--size",
        "256x256",
        "--periodic",
        "128x128",
        "--offset",
        "-77,5",
        "--bit-depth",
        "16",
    ]);
    quarters_equal(&phasor, 128);
    for f in [
        &phasor,
        &fbm,
        &ring,
        &ring_model,
        &big,
        &far,
        &periodic_model,
        &from_file,
    ] {
        std::fs::remove_file(f).unwrap();
    }
}

/// `--method gabor`: the built-in (colour) exemplar's luminance becomes a Gabor noise by
/// example with its components, `synth` renders it, and bad options name themselves.
#[test]
fn fit_and_synth_gabor_noise_by_example() {
    let dir = scratch("gabor-example");
    let model = dir.join("gabor.json");
    spectex_ok(&[
        "fit",
        "-o",
        s(&model),
        "--method",
        "gabor",
        "--grid",
        "8",
        "--seed",
        "4",
        "--bandwidths",
        "1",
    ]);
    let text = std::fs::read_to_string(&model).unwrap();
    let spectex_model::Model::Gabor(g) = spectex_model::from_json(&text).unwrap() else {
        panic!("fit --method gabor --bandwidths 1 wrote {text}")
    };
    assert!(matches!(
        g.orientation,
        spectex_model::Orientation::Spectrum { .. }
    ));
    assert_eq!(g.seed, 4);
    // Several bandwidths (the default): a sum of Gabor noises, seeds 4, 5, ….
    spectex_ok(&["fit", "-o", s(&model), "--method", "gabor", "--seed", "4"]);
    let text = std::fs::read_to_string(&model).unwrap();
    let spectex_model::Model::Combine(c) = spectex_model::from_json(&text).unwrap() else {
        panic!("fit --method gabor wrote {text}")
    };
    assert_eq!(c.op, spectex_model::combine::CombineOp::Add);
    for (k, operand) in c.operands.iter().enumerate() {
        let spectex_model::Model::Gabor(g) = operand else {
            panic!("operand {k}: {operand:?}")
        };
        assert_eq!(g.seed, 4 + k as u32);
    }
    let png = dir.join("gabor.png");
    spectex_ok(&[
        "synth",
        "-o",
        s(&png),
        "--method",
        "gabor",
        "--grid",
        "8",
        "--size",
        "64x48",
    ]);
    assert!(png.is_file());
    // The failures in a directory of their own: nothing may be left there.
    let dir = scratch("gabor-example-bad");
    let out = spectex(&[
        "fit",
        "-o",
        s(&dir.join("bad.json")),
        "--method",
        "gabor",
        "--grid",
        "60",
    ]);
    assert_fails(&out, &dir, &["grid = 60", "4..=48", "--grid"]);
    let out = spectex(&[
        "fit",
        "-o",
        s(&dir.join("bad.json")),
        "--method",
        "gabor",
        "--bandwidths",
        "5",
    ]);
    assert_fails(&out, &dir, &["bandwidths = 5", "1..=4", "--bandwidths"]);
    let out = spectex(&[
        "fit",
        "-o",
        s(&dir.join("bad.json")),
        "--method",
        "gabor",
        "--structure",
        "0.2",
    ]);
    assert_fails(&out, &dir, &["--method gabor"]);
}

/// `fit`/`synth --method tiling`: the built-in exemplar fits and renders; an exemplar smaller than
/// the tile, too small, constant or with an alpha channel is refused by name with nothing
/// written.
#[test]
fn fit_and_synth_tiling_by_example() {
    let dir = scratch("tiling-example");
    let model = dir.join("tiling.json");
    spectex_ok(&[
        "fit",
        "-o",
        s(&model),
        "--method",
        "tiling",
        "--tile",
        "24",
        "--seed",
        "5",
    ]);
    let text = std::fs::read_to_string(&model).unwrap();
    let spectex_model::Model::Tiling(t) = spectex_model::from_json(&text).unwrap() else {
        panic!("fit --method tiling wrote {text}")
    };
    assert_eq!((t.channels, t.tile, t.seed), (3, 24.0, 5));
    let png = dir.join("tiling.png");
    spectex_ok(&[
        "synth",
        "-o",
        s(&png),
        "--method",
        "tiling",
        "--blend",
        "hex",
        "--rotation",
        "0.1",
        "--size",
        "64x48",
    ]);
    assert!(png.is_file());

    let dir = scratch("tiling-example-bad");
    let inputs = scratch("tiling-example-inputs");
    let out = spectex(&[
        "fit",
        "-o",
        s(&dir.join("bad.json")),
        "--method",
        "tiling",
        "--tile",
        "200",
    ]);
    assert_fails(&out, &dir, &["tile = 200", "--tile"]);
    let small = inputs.join("small.png");
    write_png(&small, 6, 40);
    let out = spectex(&[
        "fit",
        s(&small),
        "-o",
        s(&dir.join("bad.json")),
        "--method",
        "tiling",
    ]);
    assert_fails(&out, &dir, &["image side = 6", "8 to 4096"]);
    let constant = inputs.join("constant.png");
    spectex_testkit::image_files::save(
        &image::DynamicImage::from(image::GrayImage::from_pixel(32, 32, image::Luma([90]))),
        &constant,
    )
    .unwrap();
    let out = spectex(&[
        "fit",
        s(&constant),
        "-o",
        s(&dir.join("bad.json")),
        "--method",
        "tiling",
    ]);
    assert_fails(&out, &dir, &["image", "values vary"]);
    let rgba = inputs.join("rgba.png");
    spectex_testkit::image_files::save(
        &image::DynamicImage::from(image::RgbaImage::from_fn(32, 32, |x, y| {
            image::Rgba([(x * 7) as u8, (y * 5) as u8, 40, 128])
        })),
        &rgba,
    )
    .unwrap();
    let out = spectex(&[
        "synth",
        s(&rgba),
        "-o",
        s(&dir.join("bad.png")),
        "--method",
        "tiling",
    ]);
    assert_fails(&out, &dir, &["alpha channel"]);
}
