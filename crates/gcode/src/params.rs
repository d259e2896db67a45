//! Parameters: numbered `#1`…`#5602` and named `#<name>` (local to a subroutine call) or
//! `#<_name>` (global), as LinuxCNC keeps them.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Names are short and hashed on every `#<name>` read: the multiply-rotate hash rustc uses
/// (FxHash) costs a few instructions per 8 bytes, where the default SipHash costs ~100.
#[derive(Default, Clone, Copy)]
struct NameHasher(u64);

impl NameHasher {
    const SEED: u64 = 0x51_7c_c1_b7_27_22_0a_95;

    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(Self::SEED);
    }
}

impl Hasher for NameHasher {
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            self.add(u64::from_le_bytes(c.try_into().unwrap_or([0; 8])));
        }
        let mut last = [0u8; 8];
        let rest = chunks.remainder();
        last[..rest.len()].copy_from_slice(rest);
        // The length tells "a" from "a\0" apart.
        self.add(u64::from_le_bytes(last) ^ ((rest.len() as u64) << 59));
    }

    fn write_u8(&mut self, b: u8) {
        self.add(u64::from(b));
    }

    fn write_u128(&mut self, k: u128) {
        self.add(k as u64);
        self.add((k >> 64) as u64);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

type Hashed<K, V> = HashMap<K, V, BuildHasherDefault<NameHasher>>;

/// Named values, names already lower-case. Nearly every name is at most 15 bytes: those are
/// keyed by their bytes packed in a `u128` (length in the top byte, so "a" and "a\0" differ),
/// one compare of two integers instead of a string compare, and while there are few of them
/// (a program's handful of locals) they are found by a scan, without hashing; longer names
/// are keyed by string.
#[derive(Clone, Debug, Default)]
struct NameMap {
    short: Vec<(u128, f64)>,
    /// Position in `short` by key, built once `short` outgrows a scan.
    index: Hashed<u128, usize>,
    long: Hashed<String, f64>,
}

impl NameMap {
    /// Up to this many short names a scan beats hashing.
    const SCAN: usize = 8;

    /// `name` packed as a short key (byte i at bits 8i, the length at bits 120…127), or
    /// `None` when it is longer than 15 bytes. Built from two overlapping word reads in
    /// registers: bytes stored one by one and read back as words would miss store
    /// forwarding, a stall on every lookup.
    fn pack(name: &str) -> Option<u128> {
        let b = name.as_bytes();
        let n = b.len();
        let word = |s: &[u8]| {
            let mut w = [0u8; 8];
            w[..s.len()].copy_from_slice(s);
            u64::from_le_bytes(w)
        };
        let bytes = match n {
            16.. => return None,
            // Bytes 0…7, then bytes 8…n−1: the last 8 bytes shifted past the 16 − n that
            // the first word already holds.
            8.. => {
                let tail = u128::from(word(&b[n - 8..])) >> (8 * (16 - n));
                u128::from(word(&b[..8])) | tail << 64
            }
            // Bytes 0…3, then 4…n−1 the same way.
            4.. => {
                let tail = word(&b[n - 4..]) >> (8 * (8 - n));
                u128::from(word(&b[..4]) | tail << 32)
            }
            _ => b
                .iter()
                .enumerate()
                .fold(0, |k, (i, &c)| k | u128::from(c) << (8 * i)),
        };
        Some(bytes | (n as u128) << 120)
    }

    fn slot(&self, key: u128) -> Option<usize> {
        if self.short.len() <= Self::SCAN {
            self.short.iter().position(|&(k, _)| k == key)
        } else {
            self.index.get(&key).copied()
        }
    }

    fn get(&self, name: &str) -> Option<f64> {
        match Self::pack(name) {
            Some(key) => self.slot(key).map(|i| self.short[i].1),
            None => self.long.get(name).copied(),
        }
    }

    fn get_mut(&mut self, name: &str) -> Option<&mut f64> {
        match Self::pack(name) {
            Some(key) => self.slot(key).map(|i| &mut self.short[i].1),
            None => self.long.get_mut(name),
        }
    }

    fn contains_key(&self, name: &str) -> bool {
        self.get(name).is_some()
    }

    fn insert(&mut self, name: String, value: f64) {
        if let Some(slot) = self.get_mut(&name) {
            *slot = value;
            return;
        }
        let Some(key) = Self::pack(&name) else {
            self.long.insert(name, value);
            return;
        };
        self.short.push((key, value));
        if self.short.len() > Self::SCAN {
            if self.index.is_empty() {
                self.index = self
                    .short
                    .iter()
                    .enumerate()
                    .map(|(i, &(k, _))| (k, i))
                    .collect();
            } else {
                self.index.insert(key, self.short.len() - 1);
            }
        }
    }
}

/// Highest numbered parameter (LinuxCNC's RS274NGC_MAX_PARAMETERS − 1).
pub(crate) const MAX_NUMBERED: u32 = 5602;
/// `#1`…`#30` are the arguments of a subroutine call and are local to it.
pub(crate) const CALL_ARGS: usize = 30;

#[derive(Clone, Debug)]
struct Frame {
    saved_args: [f64; CALL_ARGS],
    locals: NameMap,
}

/// Why a parameter could not be read or written.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ParamError {
    #[error("parameter #{0} is out of range (1 to {MAX_NUMBERED})")]
    OutOfRange(i64),
    #[error("named parameter #<{0}> is not defined")]
    Undefined(String),
    #[error("parameter #<{0}> is read-only")]
    ReadOnly(String),
}

/// All parameters of a run: numbered, global named, system (read-only) and the named locals
/// of each subroutine call.
#[derive(Clone, Debug)]
pub struct Params {
    numbered: Vec<f64>,
    globals: NameMap,
    /// Read-only `#<_…>` values kept up to date by the interpreter (`_x`, `_metric`, …).
    system: NameMap,
    frames: Vec<Frame>,
    top_locals: NameMap,
    /// `system` may be out of date: a block ran since the driver last refreshed it (see
    /// [`crate::exec::Executor::read_block_with`]).
    system_stale: bool,
}

impl Default for Params {
    fn default() -> Self {
        Params::new()
    }
}

impl Params {
    /// Every numbered parameter 0, no named one.
    pub fn new() -> Params {
        Params {
            numbered: vec![0.0; MAX_NUMBERED as usize + 1],
            globals: NameMap::default(),
            system: NameMap::default(),
            frames: Vec::new(),
            top_locals: NameMap::default(),
            system_stale: false,
        }
    }

    fn index(n: i64) -> Result<usize, ParamError> {
        if (0..=MAX_NUMBERED as i64).contains(&n) {
            Ok(n as usize)
        } else {
            Err(ParamError::OutOfRange(n))
        }
    }

    /// Read `#n`.
    pub fn get(&self, n: i64) -> Result<f64, ParamError> {
        Ok(self.numbered[Self::index(n)?])
    }

    /// Set `#n` (1 to the last numbered parameter).
    pub fn set(&mut self, n: i64, value: f64) -> Result<(), ParamError> {
        let i = Self::index(n)?;
        if i == 0 {
            return Err(ParamError::OutOfRange(0));
        }
        self.numbered[i] = value;
        Ok(())
    }

    /// Set `#first`, `#first+1`, … to `values` (all within 1…5602): one range check for
    /// the parameters the interpreter refreshes after every block.
    pub fn set_run(&mut self, first: i64, values: &[f64]) -> Result<(), ParamError> {
        let start = Self::index(first)?;
        if start == 0 {
            return Err(ParamError::OutOfRange(0));
        }
        let end = start + values.len();
        let slots = self
            .numbered
            .get_mut(start..end)
            .ok_or(ParamError::OutOfRange(end as i64 - 1))?;
        slots.copy_from_slice(values);
        Ok(())
    }

    fn locals(&self) -> &NameMap {
        self.frames
            .last()
            .map(|f| &f.locals)
            .unwrap_or(&self.top_locals)
    }

    /// Read `#<name>`; names are case-insensitive and compared lower-case.
    pub fn get_named(&self, name: &str) -> Result<f64, ParamError> {
        // Names from the parser are already lower-case: no copy on that (hot) path.
        let lowered;
        let key = if name.bytes().any(|b| b.is_ascii_uppercase()) {
            lowered = name.to_ascii_lowercase();
            lowered.as_str()
        } else {
            name
        };
        let found = if key.starts_with('_') {
            self.system.get(key).or_else(|| self.globals.get(key))
        } else {
            self.locals().get(key)
        };
        found.ok_or_else(|| ParamError::Undefined(key.to_string()))
    }

    /// Read the local `#<name>`, `name` already lower-case and not starting with `_`:
    /// [`Params::get_named`] without its checks, for the fast path.
    pub(crate) fn get_local(&self, name: &str) -> Option<f64> {
        debug_assert!(!name.starts_with('_') && !name.bytes().any(|b| b.is_ascii_uppercase()));
        self.locals().get(name)
    }

    /// Whether `#<name>=…` would be refused because the interpreter owns the name.
    pub fn is_read_only(&self, name: &str) -> bool {
        name.starts_with('_') && self.system.contains_key(&name.to_ascii_lowercase())
    }

    /// Say that the read-only `#<_…>` values may be out of date (a block ran).
    pub fn mark_system_stale(&mut self) {
        self.system_stale = true;
    }

    /// Whether the read-only `#<_…>` values may be out of date.
    pub fn system_stale(&self) -> bool {
        self.system_stale
    }

    /// Take the staleness mark: true (and now cleared) when the values must be refreshed.
    pub fn take_system_stale(&mut self) -> bool {
        std::mem::take(&mut self.system_stale)
    }

    /// Whether `#<name>` is defined here.
    pub fn exists_named(&self, name: &str) -> bool {
        self.get_named(name).is_ok()
    }

    /// Set `#<name>` (a local, or a global when it starts with `_`); read-only names are
    /// refused.
    pub fn set_named(&mut self, name: &str, value: f64) -> Result<(), ParamError> {
        // Updating a lower-case name that exists (the usual case) allocates nothing.
        if !name.starts_with('_') && !name.bytes().any(|b| b.is_ascii_uppercase()) {
            let locals = match self.frames.last_mut() {
                Some(f) => &mut f.locals,
                None => &mut self.top_locals,
            };
            if let Some(slot) = locals.get_mut(name) {
                *slot = value;
                return Ok(());
            }
        }
        let key = name.to_ascii_lowercase();
        if key.starts_with('_') {
            if self.system.contains_key(&key) {
                return Err(ParamError::ReadOnly(key));
            }
            self.globals.insert(key, value);
        } else {
            match self.frames.last_mut() {
                Some(f) => f.locals.insert(key, value),
                None => self.top_locals.insert(key, value),
            };
        }
        Ok(())
    }

    /// Set a read-only system parameter such as `_x` or `_metric` (interpreter only).
    pub fn set_system(&mut self, name: &str, value: f64) {
        self.system.insert(name.to_ascii_lowercase(), value);
    }

    /// Enter a subroutine: `#1`…`#30` take `args` (missing ones are 0), named locals start empty.
    pub fn push_call(&mut self, args: &[f64]) {
        let mut saved = [0.0; CALL_ARGS];
        saved.copy_from_slice(&self.numbered[1..=CALL_ARGS]);
        self.frames.push(Frame {
            saved_args: saved,
            locals: NameMap::default(),
        });
        for i in 0..CALL_ARGS {
            self.numbered[i + 1] = args.get(i).copied().unwrap_or(0.0);
        }
    }

    /// Leave a subroutine: restore the caller's `#1`…`#30` and named locals.
    pub fn pop_call(&mut self) {
        if let Some(f) = self.frames.pop() {
            self.numbered[1..=CALL_ARGS].copy_from_slice(&f.saved_args);
        }
    }

    /// Depth of subroutine calls whose locals are kept.
    pub fn call_depth(&self) -> usize {
        self.frames.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn call_frames_restore_args_and_locals() {
        let mut p = Params::new();
        p.set(1, 7.0).unwrap();
        p.set_named("a", 1.0).unwrap();
        p.push_call(&[2.0, 3.0]);
        assert_eq!(p.get(1).unwrap(), 2.0);
        assert_eq!(p.get(3).unwrap(), 0.0);
        assert!(
            p.get_named("a").is_err(),
            "locals are not visible inside a call"
        );
        p.set_named("_g", 5.0).unwrap();
        p.pop_call();
        assert_eq!(p.get(1).unwrap(), 7.0);
        assert_eq!(p.get_named("a").unwrap(), 1.0);
        assert_eq!(p.get_named("_G").unwrap(), 5.0);
    }

    #[test]
    fn many_names_of_every_length_keep_their_own_values() {
        let mut p = Params::new();
        let names: Vec<String> = (0..200)
            .map(|i| format!("{}{i}", "n".repeat(i % 19)))
            .collect();
        for (i, n) in names.iter().enumerate() {
            p.set_named(n, i as f64).unwrap();
        }
        for (i, n) in names.iter().enumerate() {
            assert_eq!(p.get_named(n).unwrap(), i as f64, "{n}");
        }
    }

    #[test]
    fn names_that_pack_alike_stay_apart_before_and_after_the_index() {
        // Same bytes but for trailing NULs or repeats: the packed key holds the length.
        let names = [
            "a",
            "a\0",
            "aa",
            "aaaa",
            "aaaaa",
            "aaaaaaaa",
            "aaaaaaaaa",
            "abcdefgh",
            "abcdefghabcdefg",
            "abcdefghabcdefgh",
            "bcdefgh",
            "x\0\0\0",
            "x",
        ];
        let mut p = Params::new();
        for (round, scale) in [(0, 1.0), (1, 10.0)] {
            for (i, n) in names.iter().enumerate() {
                p.set_named(n, i as f64 * scale).unwrap();
            }
            for (i, n) in names.iter().enumerate() {
                assert_eq!(p.get_named(n), Ok(i as f64 * scale), "{n:?} round {round}");
                assert_eq!(
                    p.get_local(n),
                    Some(i as f64 * scale),
                    "{n:?} round {round}"
                );
            }
        }
        assert!(p.get_named("aaa").is_err() && p.get_named("a\0\0").is_err());
    }

    #[test]
    fn out_of_range_and_read_only_are_errors() {
        let mut p = Params::new();
        assert_eq!(p.get(5603), Err(ParamError::OutOfRange(5603)));
        assert_eq!(
            p.set_run(5600, &[1.0, 2.0, 3.0, 4.0]),
            Err(ParamError::OutOfRange(5603))
        );
        assert_eq!(p.set_run(0, &[1.0]), Err(ParamError::OutOfRange(0)));
        p.set_run(5600, &[1.0, 2.0, 3.0]).unwrap();
        assert_eq!(p.get(5602), Ok(3.0));
        assert!(p.set(-1, 0.0).is_err());
        p.set_system("_x", 1.0);
        assert_eq!(
            p.set_named("_x", 2.0),
            Err(ParamError::ReadOnly("_x".into()))
        );
    }
}
