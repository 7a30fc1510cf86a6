//! Appending a few bytes (a word, a number's text) to a buffer with
//! copies of fixed size: `extend_from_slice` of a slice whose length is
//! known only at run time calls `memcpy`, which costs more than the copy
//! for the few bytes of a cell, and a results table appends tens of
//! millions of them.

/// Longest slice [`push`] copies itself.
const MAX: usize = 32;

/// Appends `s` to `out`: up to `MAX` bytes as two overlapping copies of
/// a fixed size, longer ones as `extend_from_slice` does.
#[inline(always)]
pub fn push(out: &mut Vec<u8>, s: &[u8]) {
    let n = s.len();
    if n > MAX {
        out.extend_from_slice(s);
        return;
    }
    let at = out.len();
    out.extend_from_slice(&[0; MAX]);
    copy_short(&mut out[at..at + n], s);
    out.truncate(at + n);
}

/// Copies `s` onto `dst` (of its length, at most `MAX` bytes) by copies
/// of fixed sizes.
#[inline(always)]
fn copy_short(dst: &mut [u8], s: &[u8]) {
    /// Copies `s`, `W <= s.len() <= 2W` bytes, as its first W and its
    /// last W bytes (overlapping in the middle).
    #[inline(always)]
    fn two<const W: usize>(dst: &mut [u8], s: &[u8]) {
        let n = s.len();
        let first: [u8; W] = s[..W].try_into().unwrap_or([0; W]);
        let last: [u8; W] = s[n - W..].try_into().unwrap_or([0; W]);
        dst[..W].copy_from_slice(&first);
        dst[n - W..n].copy_from_slice(&last);
    }
    match s.len() {
        16.. => two::<16>(dst, s),
        8.. => two::<8>(dst, s),
        4.. => two::<4>(dst, s),
        _ => dst.iter_mut().zip(s).for_each(|(d, &b)| *d = b),
    }
}

/// Room made for text of a known most length, written at a cursor: a
/// row of `lanes.csv` checks its buffer's length once, not its capacity
/// and length at every cell.
pub struct Room<'a> {
    buf: &'a mut [u8],
    at: usize,
}

impl<'a> Room<'a> {
    /// Room in `buf` from `at` to its end.
    pub fn new(buf: &'a mut [u8], at: usize) -> Self {
        Room { buf, at }
    }

    /// Writes `s` at the cursor and moves past it (panics past the room:
    /// the caller made room for the most its text can take).
    #[inline(always)]
    pub fn put(&mut self, s: &[u8]) {
        let n = s.len();
        let dst = &mut self.buf[self.at..self.at + n];
        if n > MAX {
            dst.copy_from_slice(s);
        } else {
            copy_short(dst, s);
        }
        self.at += n;
    }

    /// Where the next byte goes: the end of what was written.
    pub fn at(&self) -> usize {
        self.at
    }
}

#[cfg(test)]
mod tests {
    /// Every length from 0 to past the fixed copies, onto buffers of
    /// every fill: the same bytes as `extend_from_slice`, appended or put
    /// in a room.
    #[test]
    fn the_same_bytes_as_extend_from_slice() {
        let text: Vec<u8> = (0..80u8)
            .map(|b| b.wrapping_mul(37).wrapping_add(11))
            .collect();
        for before in [0, 1, 7, 31, 33] {
            for n in 0..=70 {
                let mut a: Vec<u8> = (0..before as u8).collect();
                let mut b = a.clone();
                super::push(&mut a, &text[..n]);
                b.extend_from_slice(&text[..n]);
                assert_eq!(a, b, "{before} bytes before, {n} appended");
                // The same bytes through a room made for them (and
                // around them, which stays as it was).
                let mut c: Vec<u8> = (0..before as u8).chain([7; 80]).collect();
                let mut room = super::Room::new(&mut c, before);
                room.put(&text[..n]);
                assert_eq!(room.at(), before + n);
                assert_eq!(
                    &c[..before + n],
                    &b[..],
                    "a room, {before} bytes before, {n} put"
                );
                assert!(c[before + n..].iter().all(|&x| x == 7));
            }
        }
    }
}
