//! Is it HP-GL? Plotter files arrive as `.plt`, `.hpg`, `.hp`, `.hgl`, `.prn`, `.000` or no
//! extension at all, so the content decides: a PCL or device-control escape that HP-GL files
//! start with, or a first instruction that opens plots (IN, DF, SP, PU, PA, IP, SC, BP, …)
//! followed by what can follow an instruction, and a second instruction after it.

/// Extensions that are HP-GL whatever their content looks like.
pub const HPGL_EXTENSIONS: &[&str] = &["hpgl", "hpgl2", "hpg", "hp", "hgl", "plt", "gl", "gl2"];

/// Instructions that plot files begin with.
const OPENERS: &[&[u8; 2]] = &[
    b"IN", b"DF", b"SP", b"PU", b"PD", b"PA", b"PR", b"IP", b"IR", b"SC", b"BP", b"PS", b"RO",
    b"VS", b"LT", b"PG", b"CO", b"DT", b"SI", b"PW", b"WU", b"NP", b"MC", b"TR", b"OI", b"CS",
    b"CA", b"SD", b"SR", b"LA", b"PM", b"FT", b"PT", b"QL", b"PC",
];

/// Every HP-GL and HP-GL/2 instruction (HP 7475A, 7550A and the HP-GL/2 reference).
const KNOWN: &[&[u8; 2]] = &[
    b"AA", b"AC", b"AD", b"AF", b"AH", b"AP", b"AR", b"AS", b"AT", b"BF", b"BL", b"BP", b"BR",
    b"BZ", b"CA", b"CC", b"CF", b"CI", b"CM", b"CO", b"CP", b"CR", b"CS", b"CT", b"CV", b"DC",
    b"DF", b"DI", b"DL", b"DP", b"DR", b"DS", b"DT", b"DV", b"EA", b"EC", b"EP", b"ER", b"ES",
    b"EW", b"FI", b"FN", b"FP", b"FR", b"FS", b"FT", b"GC", b"GM", b"GP", b"IM", b"IN", b"IP",
    b"IR", b"IV", b"IW", b"KY", b"LA", b"LB", b"LM", b"LO", b"LT", b"MC", b"MG", b"MT", b"NP",
    b"NR", b"OA", b"OC", b"OD", b"OE", b"OF", b"OG", b"OH", b"OI", b"OL", b"OO", b"OP", b"OS",
    b"OT", b"OW", b"PA", b"PB", b"PC", b"PD", b"PE", b"PG", b"PM", b"PP", b"PR", b"PS", b"PT",
    b"PU", b"PW", b"QL", b"RA", b"RF", b"RO", b"RP", b"RR", b"RT", b"SA", b"SB", b"SC", b"SD",
    b"SG", b"SI", b"SL", b"SM", b"SP", b"SR", b"SS", b"ST", b"SV", b"TD", b"TL", b"TR", b"UC",
    b"UF", b"UL", b"VS", b"WD", b"WG", b"WU", b"XT", b"YT",
];

/// Whether `m` is an HP-GL or HP-GL/2 instruction.
pub(super) fn is_known(m: &[u8; 2]) -> bool {
    KNOWN.contains(&m)
}

/// Whether `bytes` (the first kilobytes of a file suffice) look like HP-GL, HP-GL/2 or PCL
/// with HP-GL/2 inside.
pub fn looks_like_hpgl(bytes: &[u8]) -> bool {
    let b = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let start = b.iter().position(|c| {
        !matches!(
            c,
            b' ' | b'\t' | b'\r' | b'\n' | 0 | 0x03 | 0x0c | 0x1a | b';'
        )
    });
    let Some(start) = start else { return false };
    let b = &b[start..];
    if b[0] == 0x1b {
        // ESC . (device control), ESC E (PCL reset), ESC % (UEL, HP-GL/2 mode), ESC & / ESC *
        // (PCL page and raster set-up): the languages HP plotters and printers speak.
        return matches!(b.get(1), Some(b'.' | b'E' | b'%' | b'&' | b'*'));
    }
    let two = |at: usize| -> Option<[u8; 2]> {
        let (a, c) = (*b.get(at)?, *b.get(at + 1)?);
        (a.is_ascii_alphabetic() && c.is_ascii_alphabetic())
            .then(|| [a.to_ascii_uppercase(), c.to_ascii_uppercase()])
    };
    let Some(first) = two(0) else { return false };
    if !OPENERS.contains(&&first) {
        return false;
    }
    // What follows: a terminator, parameters, or at once the next instruction; then a second
    // instruction must come within the next few bytes.
    let mut i = 2;
    while i < b.len() && i < 64 {
        let c = b[i];
        if c.is_ascii_digit()
            || matches!(
                c,
                b',' | b'-' | b'+' | b'.' | b' ' | b'"' | b'\r' | b'\n' | b'\t'
            )
        {
            i += 1;
            continue;
        }
        if c == b';' {
            i += 1;
            while i < b.len() && matches!(b[i], b' ' | b'\r' | b'\n' | b'\t' | b';') {
                i += 1;
            }
            return i >= b.len() || b[i] == 0x1b || two(i).is_some_and(|m| KNOWN.contains(&&m));
        }
        return two(i).is_some_and(|m| KNOWN.contains(&&m));
    }
    i >= b.len()
}

#[cfg(test)]
mod tests {
    use super::looks_like_hpgl;

    #[test]
    fn hpgl_in_its_forms_is_recognised() {
        for s in [
            &b"IN;SP1;PU0,0;PD100,0;"[..],
            b"in;sp1;pa0,0;",
            b"\x1b.(;\x1b.I81;;17:IN;SC;",
            b"\x1b%-12345X@PJL ENTER LANGUAGE=HPGL2\r\n",
            b"\x1bE\x1b%0BIN;",
            b"\r\nIN\r\nSP1\r\n",
            b"\x03INCA2IP0,0,10300,7650DI0,1SP2",
            b"SP1;\nPA2640,1753;\nPD;",
            b"INPU0,0PD10,10",
            b"IN",
        ] {
            assert!(looks_like_hpgl(s), "{}", String::from_utf8_lossy(s));
        }
    }

    #[test]
    fn other_drawings_are_not_hpgl() {
        for s in [
            &b"<?xml version=\"1.0\"?><svg/>"[..],
            b"  0\nSECTION\n  2\nHEADER\n",
            b"AutoCAD Binary DXF\r\n\x1a\x00",
            b"10,20\n30,40\n",
            b"G21 G90\nG0 X0 Y0\n",
            b"Pictures of a plotter",
            b"Info: nothing",
            b"",
            b"INVOICE 2024",
            b"%!PS-Adobe-3.0",
        ] {
            assert!(!looks_like_hpgl(s), "{}", String::from_utf8_lossy(s));
        }
    }
}
