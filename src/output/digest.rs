//! SHA-256 digests of files: computed while a file is written or read
//! ([`Hashing`]), or of a whole file ([`file_digest`]), as a shard's
//! manifest records them.

use std::io::{Read, Write};
use std::path::Path;

use sha2::{Digest, Sha256};

use crate::error::{Error, Result};

/// The size and SHA-256 of a file a manifest covers.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct FileDigest {
    /// Its size in bytes.
    pub bytes: u64,
    /// Its SHA-256, as `sha256:` and 64 hex digits.
    pub sha256: String,
}

/// A SHA-256 as the manifests write it.
pub fn hex(digest: &[u8]) -> String {
    let mut s = String::from("sha256:");
    for b in digest {
        s.push_str(&format!("{b:02x}"));
    }
    s
}

/// A writer or reader that hashes (SHA-256) what passes through it, or
/// only passes it on.
pub struct Hashing<W> {
    inner: W,
    hash: Option<Box<Sha256>>,
    bytes: u64,
}

impl<W> Hashing<W> {
    /// Hashes what passes through `inner`.
    pub fn new(inner: W) -> Hashing<W> {
        Hashing {
            inner,
            hash: Some(Box::new(Sha256::new())),
            bytes: 0,
        }
    }

    /// Passes through `inner` without hashing.
    pub(crate) fn unhashed(inner: W) -> Hashing<W> {
        Hashing {
            inner,
            hash: None,
            bytes: 0,
        }
    }

    /// The size and digest of everything so far (None when not hashing).
    pub fn digest(&self) -> Option<FileDigest> {
        self.hash.as_ref().map(|h| FileDigest {
            bytes: self.bytes,
            sha256: hex(&(**h).clone().finalize()),
        })
    }

    /// The inner writer or reader.
    pub(crate) fn get_ref(&self) -> &W {
        &self.inner
    }

    fn saw(&mut self, buf: &[u8]) {
        if let Some(h) = self.hash.as_mut() {
            h.update(buf);
        }
        self.bytes += buf.len() as u64;
    }
}

impl<W: Write> Write for Hashing<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.saw(&buf[..n]);
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

impl<R: Read> Read for Hashing<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.saw(&buf[..n]);
        Ok(n)
    }
}

/// The size and SHA-256 of the file `path`.
pub fn file_digest(path: &Path) -> Result<FileDigest> {
    let f = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut h = Hashing::new(std::io::BufReader::with_capacity(1 << 20, f));
    std::io::copy(&mut h, &mut std::io::sink()).map_err(|e| Error::io(path, e))?;
    Ok(h.digest().expect("hashing"))
}
