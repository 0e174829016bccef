//! Per-thread caches of the row tables: reused buffers, kept column hashes and corner tables.

use super::simplex::SimplexCorners;
use super::tables::column_hashes;

thread_local! {
    /// The [`SimplexCorners`] of this thread's last rows: rows a few pixels apart share their
    /// skewed rows, `d_lo` and `e_lo`, and building the table cost about 3–6% of a 3D simplex
    /// row.
    pub(super) static KEPT_CORNERS: std::cell::RefCell<Vec<SimplexCorners>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// [`SimplexCorners`] tables [`KEPT_CORNERS`] keeps at most.
pub(super) const KEPT_CORNER_TABLES: usize = 16;

thread_local! {
    /// Buffers of the tables of the rows this thread evaluated before: a table of cells of
    /// one pixel is as long as its row, and allocating it afresh for each row (zeroed pages
    /// from the system) cost about a sixth of a 3D fBm's time.
    pub(super) static BUFFERS: std::cell::RefCell<Vec<Vec<u32>>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// Buffers [`BUFFERS`] keeps at most (a row's tables: up to 3 per octave).
pub(super) const KEPT_BUFFERS: usize = 64;

/// `size` zeros in a buffer of an earlier row where this thread has one.
pub(super) fn buffer(size: usize) -> Vec<u32> {
    let mut v = scratch(size);
    v.fill(0);
    v
}

/// `size` entries of unspecified values (an earlier row's, or zeros) in a buffer of an earlier
/// row where this thread has one, for a table whose builder writes every entry it reads:
/// zeroing a row's tables first cost 8% of a 3D fBm's time.
pub(super) fn scratch(size: usize) -> Vec<u32> {
    // Growing a buffer zeroes its new entries only; a row gives its buffers back in reverse,
    // so the next row's tables get the buffers of the same sizes.
    let mut v = BUFFERS.with(|b| b.borrow_mut().pop()).unwrap_or_default();
    v.resize(size, 0);
    v
}

thread_local! {
    /// The column hashes of the row keys this thread's last rows used ([`KeptHashes`]).
    pub(super) static KEPT: std::cell::RefCell<KeptHashes> =
        std::cell::RefCell::new(KeptHashes::default());
}

/// Row keys whose column hashes [`KEPT`] keeps at most (direct-mapped by the key's low bits).
pub(super) const KEPT_KEYS: usize = 64;
/// Columns of the rows whose hashes [`KEPT`] keeps at most (a thread keeps at most 4 MiB);
/// longer rows hash their columns for each row.
pub(super) const KEPT_COLUMNS: usize = 1 << 14;

/// The [`column_hashes`] of the row keys of this thread's last rows, by row key, first column
/// and period: rows in one cell share their row keys, and a row's `j + 1` (`k + 1`) is the next
/// cell's `j` (`k`), so a 3D fBm's rows hashed most of their columns again (a pure function of
/// the three, so a kept entry is the very hashes).
#[derive(Debug, Default)]
pub(super) struct KeptHashes {
    /// `(key, lo, cells)` of each entry ([`KEPT_KEYS`] once used).
    pub(super) ids: Vec<Option<(u32, i32, i32)>>,
    pub(super) hashes: Vec<Vec<u32>>,
    /// The hashes of a row longer than [`KEPT_COLUMNS`], not kept.
    pub(super) spare: Vec<u32>,
}

impl KeptHashes {
    /// `column_hashes(lo, cells, key)` of `count` columns, kept or computed.
    #[inline(always)]
    pub(super) fn get(&mut self, lo: i32, cells: i32, key: u32, count: usize) -> &[u32] {
        if count > KEPT_COLUMNS {
            self.spare.resize(count, 0);
            column_hashes(lo, cells, key, &mut self.spare);
            return &self.spare;
        }
        if self.ids.is_empty() {
            self.ids = vec![None; KEPT_KEYS];
            self.hashes = vec![Vec::new(); KEPT_KEYS];
        }
        // One entry per key's low bits (a row key is a hash): a lookup is one comparison, where
        // a search of every entry cost rows of 256 pixels a fifth of their time.
        let id = (key, lo, cells);
        let e = (key ^ lo as u32 ^ (cells as u32).wrapping_mul(0x9E37_79B9)) as usize % KEPT_KEYS;
        let v = &mut self.hashes[e];
        if self.ids[e] != Some(id) || v.len() < count {
            self.ids[e] = Some(id);
            v.resize(count, 0);
            column_hashes(lo, cells, key, v);
        }
        &v[..count]
    }
}

/// Gives `v` back for a later row's [`buffer`].
pub(super) fn recycle(v: Vec<u32>) {
    if v.capacity() > 0 {
        BUFFERS.with(|b| {
            let mut b = b.borrow_mut();
            if b.len() < KEPT_BUFFERS {
                b.push(v);
            }
        });
    }
}
