//! Reading and writing image files in tests, compiled once, here.
//!
//! `image::open`, `image::load_from_memory` and `ImageBuffer::save` are generic over their
//! reader or writer, so every crate that calls them compiles the PNG, JPEG and OpenEXR codecs
//! again at its own optimisation level: a test binary that opened one PNG spent most of its
//! compilation there (spectex-simulate's `it`: 60 of its 64 unit-seconds in a loaded CI-like
//! build, the codecs' functions the largest in its LLVM IR). These functions are not generic, so
//! the codecs are compiled in this crate once and the tests link to them.

use std::path::Path;

use image::{DynamicImage, ImageResult};

/// [`image::open`]: the file's format from its extension, then from its bytes.
pub fn open(path: impl AsRef<Path>) -> ImageResult<DynamicImage> {
    open_path(path.as_ref())
}

#[inline(never)]
fn open_path(path: &Path) -> ImageResult<DynamicImage> {
    image::open(path)
}

/// [`image::load_from_memory`]: an encoded image's format from its bytes.
#[inline(never)]
pub fn load_from_memory(bytes: &[u8]) -> ImageResult<DynamicImage> {
    image::load_from_memory(bytes)
}

/// [`DynamicImage::save`]: the format from the path's extension.
pub fn save(image: &DynamicImage, path: impl AsRef<Path>) -> ImageResult<()> {
    save_path(image, path.as_ref())
}

#[inline(never)]
fn save_path(image: &DynamicImage, path: &Path) -> ImageResult<()> {
    image.save(path)
}
