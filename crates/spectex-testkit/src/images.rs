//! Image files for fuzzing an image loader, written byte by byte so that any header can be
//! claimed: PNGs of every colour type and bit depth (grey 1–16 bit, grey+alpha, RGB, RGBA,
//! palette, interlaced), and broken ones — truncated, headers claiming 100000×100000 or zero
//! pixels, impossible type/depth pairs, bad checksums, a palette missing, too little pixel data —
//! plus a JPEG header patcher and byte-level mutations for any file.

use proptest::prelude::*;
use proptest::sample::Index;

/// A PNG's `IHDR` fields.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ihdr {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Bits per sample (1, 2, 4, 8, 16 where the colour type allows).
    pub bit_depth: u8,
    /// 0 grey, 2 RGB, 3 palette, 4 grey+alpha, 6 RGBA.
    pub colour_type: u8,
    /// 0 none, 1 Adam7.
    pub interlace: u8,
}

/// Samples per pixel of a PNG colour type (`None` for a type PNG does not define).
#[must_use]
pub fn samples_per_pixel(colour_type: u8) -> Option<usize> {
    match colour_type {
        0 | 3 => Some(1),
        4 => Some(2),
        2 => Some(3),
        6 => Some(4),
        _ => None,
    }
}

/// The bit depths PNG allows for a colour type.
#[must_use]
pub fn allowed_depths(colour_type: u8) -> &'static [u8] {
    match colour_type {
        0 => &[1, 2, 4, 8, 16],
        3 => &[1, 2, 4, 8],
        2 | 4 | 6 => &[8, 16],
        _ => &[],
    }
}

/// CRC-32 (ISO 3309, as PNG uses), bit by bit.
#[must_use]
pub fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A zlib stream holding `data` in stored (uncompressed) deflate blocks.
#[must_use]
pub fn zlib_stored(data: &[u8]) -> Vec<u8> {
    let mut out = vec![0x78, 0x01];
    let mut blocks = data.chunks(65_535).peekable();
    if blocks.peek().is_none() {
        out.extend([1, 0, 0, 0xFF, 0xFF]);
    }
    while let Some(block) = blocks.next() {
        let last = u8::from(blocks.peek().is_none());
        let len = block.len() as u16;
        out.push(last);
        out.extend(len.to_le_bytes());
        out.extend((!len).to_le_bytes());
        out.extend(block);
    }
    let (mut a, mut b) = (1u32, 0u32);
    for &byte in data {
        a = (a + u32::from(byte)) % 65_521;
        b = (b + a) % 65_521;
    }
    out.extend(((b << 16) | a).to_be_bytes());
    out
}

/// One PNG chunk: length, tag, data, CRC.
#[must_use]
pub fn chunk(tag: &[u8; 4], data: &[u8]) -> Vec<u8> {
    let mut out = (data.len() as u32).to_be_bytes().to_vec();
    out.extend(tag);
    out.extend(data);
    let mut crc_input = tag.to_vec();
    crc_input.extend(data);
    out.extend(crc32(&crc_input).to_be_bytes());
    out
}

/// The PNG signature.
pub const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];

/// The 13 bytes of an `IHDR` chunk's data.
#[must_use]
pub fn ihdr_data(h: &Ihdr) -> Vec<u8> {
    let mut d = h.width.to_be_bytes().to_vec();
    d.extend(h.height.to_be_bytes());
    d.extend([h.bit_depth, h.colour_type, 0, 0, h.interlace]);
    d
}

/// A PNG: signature, `IHDR`, a `PLTE` when given, one `IDAT` holding `raw` (filter bytes and
/// scanlines), `IEND`.
#[must_use]
pub fn png(h: &Ihdr, palette: Option<&[[u8; 3]]>, raw: &[u8]) -> Vec<u8> {
    let mut out = PNG_SIGNATURE.to_vec();
    out.extend(chunk(b"IHDR", &ihdr_data(h)));
    if let Some(p) = palette {
        out.extend(chunk(b"PLTE", &p.concat()));
    }
    out.extend(chunk(b"IDAT", &zlib_stored(raw)));
    out.extend(chunk(b"IEND", &[]));
    out
}

/// Bytes of one scanline (without its filter byte).
#[must_use]
pub fn row_bytes(width: usize, bit_depth: u8, colour_type: u8) -> usize {
    let bits = width * samples_per_pixel(colour_type).unwrap_or(1) * usize::from(bit_depth);
    bits.div_ceil(8)
}

/// The raw image data (filter type 0 per row) of a valid `h` without interlacing, with sample
/// bytes from a fixed pattern (`(x·7 + y·13 + k) mod 256`, palette indices within `palette_len`).
#[must_use]
pub fn raw_rows(h: &Ihdr, palette_len: usize) -> Vec<u8> {
    let (w, ht) = (h.width as usize, h.height as usize);
    let row = row_bytes(w, h.bit_depth, h.colour_type);
    let mut raw = Vec::with_capacity((row + 1) * ht);
    for y in 0..ht {
        raw.push(0);
        for k in 0..row {
            let mut b = ((k * 7 + y * 13) % 256) as u8;
            if h.colour_type == 3 {
                // Every index packed in the byte must name a palette entry.
                let per_byte = 8 / usize::from(h.bit_depth).max(1);
                let mut packed = 0u8;
                for i in 0..per_byte {
                    let index = ((k * per_byte + i + y) % palette_len.max(1)) as u8;
                    packed |= index << (8 - usize::from(h.bit_depth) * (i + 1));
                }
                b = packed;
            }
            raw.push(b);
        }
    }
    raw
}

/// The raw data of an Adam7-interlaced `h`: each non-empty pass's rows, filter type 0.
#[must_use]
pub fn raw_interlaced(h: &Ihdr, palette_len: usize) -> Vec<u8> {
    const PASSES: [(usize, usize, usize, usize); 7] = [
        (0, 0, 8, 8),
        (4, 0, 8, 8),
        (0, 4, 4, 8),
        (2, 0, 4, 4),
        (0, 2, 2, 4),
        (1, 0, 2, 2),
        (0, 1, 1, 2),
    ];
    let (w, ht) = (h.width as usize, h.height as usize);
    let mut raw = Vec::new();
    for (x0, y0, dx, dy) in PASSES {
        let pw = if w > x0 { (w - x0).div_ceil(dx) } else { 0 };
        let ph = if ht > y0 { (ht - y0).div_ceil(dy) } else { 0 };
        if pw == 0 || ph == 0 {
            continue;
        }
        let pass = Ihdr {
            width: pw as u32,
            height: ph as u32,
            interlace: 0,
            ..*h
        };
        raw.extend(raw_rows(&pass, palette_len));
    }
    raw
}

/// A valid PNG of `h` (palette images get a palette of 5 colours).
#[must_use]
pub fn valid_png(h: &Ihdr) -> Vec<u8> {
    let palette: Vec<[u8; 3]> = (0..5u8).map(|i| [i * 50, 255 - i * 40, i * 17]).collect();
    let raw = if h.interlace == 1 {
        raw_interlaced(h, palette.len())
    } else {
        raw_rows(h, palette.len())
    };
    png(h, (h.colour_type == 3).then_some(palette.as_slice()), &raw)
}

/// Every valid colour type and bit depth at a few sizes (2×2 and up), interlaced or not: what a
/// loader that says it reads PNG must read.
#[must_use]
pub fn valid_pngs() -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for colour_type in [0u8, 2, 3, 4, 6] {
        for &bit_depth in allowed_depths(colour_type) {
            for (width, height, interlace) in [(2, 2, 0), (3, 2, 0), (17, 5, 0), (9, 10, 1)] {
                let h = Ihdr {
                    width,
                    height,
                    bit_depth,
                    colour_type,
                    interlace,
                };
                out.push((format!("{h:?}"), valid_png(&h)));
            }
        }
    }
    out
}

/// Broken PNGs, each named by what is wrong: the loader must refuse every one with a message.
#[must_use]
pub fn malformed_pngs() -> Vec<(String, Vec<u8>)> {
    let rgb = Ihdr {
        width: 4,
        height: 3,
        bit_depth: 8,
        colour_type: 2,
        interlace: 0,
    };
    let good = valid_png(&rgb);
    let mut out: Vec<(String, Vec<u8>)> = Vec::new();
    // Cut in the signature, the header, the pixel data and the end chunk's length (a cut inside
    // the end chunk's tag or checksum leaves a whole image, which decoders may read).
    for cut in [0, 4, 8, 12, 20, 33, 40, 60, good.len() - 13] {
        out.push((format!("truncated to {cut} bytes"), good[..cut].to_vec()));
    }
    // Headers claiming huge, zero or extreme sizes, with a little data after them.
    let tiny = zlib_stored(&[0, 1, 2, 3]);
    for (width, height, colour_type, bit_depth) in [
        (100_000, 100_000, 2, 8),
        (100_000, 1, 0, 8),
        (1, 100_000, 6, 16),
        (16_385, 16_385, 0, 8),
        (16_384, 16_384, 6, 16),
        (0, 0, 2, 8),
        (0, 5, 0, 8),
        (5, 0, 0, 8),
        (u32::MAX, u32::MAX, 6, 16),
        (0x8000_0000, 1, 0, 8),
    ] {
        let h = Ihdr {
            width,
            height,
            bit_depth,
            colour_type,
            interlace: 0,
        };
        let mut bytes = PNG_SIGNATURE.to_vec();
        bytes.extend(chunk(b"IHDR", &ihdr_data(&h)));
        bytes.extend(chunk(b"IDAT", &tiny));
        bytes.extend(chunk(b"IEND", &[]));
        out.push((
            format!("header claims {width}×{height} (type {colour_type}, {bit_depth}-bit)"),
            bytes,
        ));
    }
    // Colour type and bit depth pairs PNG does not define.
    for (colour_type, bit_depth) in [
        (2, 4),
        (6, 1),
        (3, 16),
        (4, 2),
        (1, 8),
        (7, 8),
        (0, 3),
        (0, 0),
        (2, 255),
    ] {
        let h = Ihdr {
            colour_type,
            bit_depth,
            ..rgb
        };
        let raw = vec![0u8; (row_bytes(4, bit_depth.max(1), colour_type) + 1) * 3];
        out.push((
            format!("colour type {colour_type} with {bit_depth}-bit samples"),
            png(&h, None, &raw),
        ));
    }
    let palette = Ihdr {
        colour_type: 3,
        ..rgb
    };
    out.push((
        "palette image without a PLTE chunk".into(),
        png(&palette, None, &raw_rows(&palette, 5)),
    ));
    out.push((
        "an empty PLTE".into(),
        png(&palette, Some(&[]), &raw_rows(&palette, 1)),
    ));
    out.push((
        "interlace method 7".into(),
        png(
            &Ihdr {
                interlace: 7,
                ..rgb
            },
            None,
            &raw_rows(&rgb, 0),
        ),
    ));
    let raw = raw_rows(&rgb, 0);
    out.push((
        "half the pixel data".into(),
        png(&rgb, None, &raw[..raw.len() / 2]),
    ));
    out.push(("no pixel data".into(), png(&rgb, None, &[])));
    let mut bad_filter = raw.clone();
    bad_filter[0] = 9;
    out.push(("filter type 9".into(), png(&rgb, None, &bad_filter)));
    let mut bad_crc = good.clone();
    let at = 8 + 8 + 13; // the IHDR CRC
    bad_crc[at] ^= 0xFF;
    out.push(("IHDR checksum wrong".into(), bad_crc));
    let mut no_ihdr = PNG_SIGNATURE.to_vec();
    no_ihdr.extend(chunk(b"IDAT", &zlib_stored(&raw)));
    no_ihdr.extend(chunk(b"IEND", &[]));
    out.push(("no IHDR chunk".into(), no_ihdr));
    let mut bad_zlib = PNG_SIGNATURE.to_vec();
    bad_zlib.extend(chunk(b"IHDR", &ihdr_data(&rgb)));
    bad_zlib.extend(chunk(b"IDAT", &[0x78, 0x01, 0xFF, 0xFF, 0xFF, 0xFF]));
    bad_zlib.extend(chunk(b"IEND", &[]));
    out.push(("corrupt deflate stream".into(), bad_zlib));
    let mut huge_chunk = PNG_SIGNATURE.to_vec();
    huge_chunk.extend(chunk(b"IHDR", &ihdr_data(&rgb)));
    huge_chunk.extend(0xFFFF_FFF0u32.to_be_bytes());
    huge_chunk.extend(b"IDAT");
    huge_chunk.extend([0u8; 16]);
    out.push(("a chunk claiming 4 GiB of data".into(), huge_chunk));
    out.push(("the signature alone".into(), PNG_SIGNATURE.to_vec()));
    out.push(("empty file".into(), Vec::new()));
    out.push(("text".into(), b"{\"not\": \"an image\"}".to_vec()));
    out
}

/// A JPEG's bytes with the dimensions of its first frame header (`SOF0` to `SOF15`, except the
/// `DHT`/`JPG`/`DAC` markers) replaced; `None` when it has none.
#[must_use]
pub fn patch_jpeg_dimensions(jpeg: &[u8], width: u16, height: u16) -> Option<Vec<u8>> {
    let mut i = 2;
    while i + 9 < jpeg.len() {
        if jpeg[i] != 0xFF {
            return None;
        }
        let marker = jpeg[i + 1];
        let len = usize::from(u16::from_be_bytes([jpeg[i + 2], jpeg[i + 3]]));
        if (0xC0..=0xCF).contains(&marker) && !matches!(marker, 0xC4 | 0xC8 | 0xCC) {
            let mut out = jpeg.to_vec();
            out[i + 5..i + 7].copy_from_slice(&height.to_be_bytes());
            out[i + 7..i + 9].copy_from_slice(&width.to_be_bytes());
            return Some(out);
        }
        i += 2 + len;
    }
    None
}

/// A byte-level mutation of a file.
#[derive(Debug, Clone)]
pub enum ByteMutation {
    /// Cut at a byte.
    Truncate(Index),
    /// Bytes xor-ed with a value, from an index on, a number of them.
    Flip(Index, u8, usize),
    /// A run of bytes removed.
    Remove(Index, usize),
    /// A big-endian `u32` written at an index (a length, a width, a height…).
    Word(Index, u32),
}

/// Byte mutations: truncations, flipped runs, removed runs, words of extreme values.
pub fn byte_mutation() -> BoxedStrategy<ByteMutation> {
    let word = prop_oneof![
        Just(0u32),
        Just(1),
        Just(16_385),
        Just(100_000),
        Just(0x7FFF_FFFF),
        Just(u32::MAX),
        any::<u32>(),
    ];
    prop_oneof![
        any::<Index>().prop_map(ByteMutation::Truncate),
        (any::<Index>(), 1u8..=255, 1usize..4).prop_map(|(i, x, n)| ByteMutation::Flip(i, x, n)),
        (any::<Index>(), 1usize..64).prop_map(|(i, n)| ByteMutation::Remove(i, n)),
        (any::<Index>(), word).prop_map(|(i, w)| ByteMutation::Word(i, w)),
    ]
    .boxed()
}

/// Applies `m` to `bytes`.
#[must_use]
pub fn mutate_bytes(bytes: &[u8], m: &ByteMutation) -> Vec<u8> {
    let mut out = bytes.to_vec();
    let len = out.len().max(1);
    match m {
        ByteMutation::Truncate(i) => out.truncate(i.index(len)),
        ByteMutation::Flip(i, x, n) => {
            let start = i.index(len);
            for b in out.iter_mut().skip(start).take(*n) {
                *b ^= x;
            }
        }
        ByteMutation::Remove(i, n) => {
            let start = i.index(len).min(out.len());
            let end = (start + n).min(out.len());
            out.drain(start..end);
        }
        ByteMutation::Word(i, w) => {
            let start = i.index(len).min(out.len().saturating_sub(4));
            for (b, v) in out.iter_mut().skip(start).zip(w.to_be_bytes()) {
                *b = v;
            }
        }
    }
    out
}

/// A random PNG header (any width, height, depth, type and interlace byte, extremes
/// included) over a small valid or truncated body: most are refused.
pub fn random_png() -> BoxedStrategy<(String, Vec<u8>)> {
    let side = prop_oneof![
        4 => 1u32..=24,
        1 => Just(0u32),
        1 => Just(16_384u32),
        1 => Just(16_385u32),
        1 => Just(100_000u32),
        1 => any::<u32>(),
    ];
    let depth =
        prop_oneof![4 => proptest::sample::select(vec![1u8, 2, 4, 8, 16]), 1 => any::<u8>()];
    let colour =
        prop_oneof![4 => proptest::sample::select(vec![0u8, 2, 3, 4, 6]), 1 => any::<u8>()];
    let interlace = prop_oneof![4 => Just(0u8), 2 => Just(1u8), 1 => any::<u8>()];
    (
        side.clone(),
        side,
        depth,
        colour,
        interlace,
        any::<bool>(),
        any::<Index>(),
    )
        .prop_map(
            |(width, height, bit_depth, colour_type, interlace, cut, at)| {
                let h = Ihdr {
                    width,
                    height,
                    bit_depth,
                    colour_type,
                    interlace,
                };
                let small = width <= 64 && height <= 64;
                let valid =
                    small && allowed_depths(colour_type).contains(&bit_depth) && interlace <= 1;
                let mut bytes = if valid {
                    valid_png(&h)
                } else {
                    let mut b = PNG_SIGNATURE.to_vec();
                    b.extend(chunk(b"IHDR", &ihdr_data(&h)));
                    b.extend(chunk(b"IDAT", &zlib_stored(&[0; 64])));
                    b.extend(chunk(b"IEND", &[]));
                    b
                };
                if cut {
                    bytes.truncate(at.index(bytes.len()));
                }
                (
                    format!("{h:?}{}", if cut { ", truncated" } else { "" }),
                    bytes,
                )
            },
        )
        .boxed()
}
