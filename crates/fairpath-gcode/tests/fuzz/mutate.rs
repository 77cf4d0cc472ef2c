//! Mutations of G-code text and of the JSON pieces format: byte flips,
//! insertions of tokens the reader treats specially, numbers at the edges
//! of f64, line deletions, duplications and swaps, random G and M codes,
//! and for JSON, changes of degrees, knots, points and weights.

use super::rng::Rng;
use serde_json::{json, Value};

/// Tokens the lexer and interpreter handle specially (or reject), and
/// syntax of other dialects.
const TOKENS: &[&str] = &[
    "#",
    "#1=5",
    "#<x>",
    "[",
    "]",
    "[1+2]",
    "[#1*2]",
    "o100 sub",
    "o100 endsub",
    "o100 call",
    "O1234",
    "G81",
    "G81 R1 Z-1",
    "/",
    "/2",
    "E5",
    "(",
    ")",
    "(msg)",
    ";",
    ";c",
    "\r",
    "\n",
    "\r\n",
    "%",
    "N",
    "N10",
    "N99999999999",
    "-",
    "+",
    ".",
    "..",
    "-.",
    "NaN",
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e-308",
    "1e400",
    "5e-324",
    "0",
    "-0",
    "0.0000001",
    "E",
    "99999999999999999999999999999999999999",
    "\0",
    "\t",
    " ",
    "\u{7f}",
    "\u{e9}",
    "\u{feff}",
    "G5.2",
    "G5.3",
    "G6.2",
    "G5",
    "G5.1",
    "G2",
    "G3",
    "G0",
    "G1",
    "G20",
    "G21",
    "G90",
    "G91",
    "G90.1",
    "G91.1",
    "G17",
    "G18",
    "G19",
    "G64 P0.01",
    "G64 P1 Q1",
    "G61",
    "G41 D1",
    "G40",
    "G43 H1",
    "G49",
    "G92 X0",
    "G92.1",
    "G28",
    "G53 G0 X0",
    "G54",
    "G59.3",
    "G93",
    "G94",
    "G95",
    "G33 K1",
    "G38.2 Z-1",
    "G4 P1",
    "G10 L2 P1 X0",
    "G7",
    "G16",
    "G51",
    "G68",
    "G80",
    "M2",
    "M30",
    "M3 S1000",
    "M6 T1",
    "T1",
    "S100",
    "F0",
    "F-1",
    "F1e308",
    "P",
    "P0",
    "P-1",
    "P1.5",
    "P1000000",
    "L",
    "L3",
    "Q",
    "Q1",
    "Q4",
    "K",
    "K0",
    "R",
    "R0",
    "R-1",
    "I",
    "J",
    "X",
    "Y",
    "Z",
    "A",
    "B",
    "C",
    "U",
    "V",
    "W",
    "X1",
    "Y-1",
    "Z1e-9",
    "I1e300",
    "R1e-300",
    "X1e300",
];

/// Numbers at the edges of f64 and of the reader's ranges.
const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1",
    "-1",
    "0.5",
    "1e308",
    "-1e308",
    "1e-308",
    "1.7976931348623157e308",
    "4.9e-324",
    "1e400",
    "123456789012345678901234567890",
    "0.000000000001",
    "2147483648",
    "4294967296",
    "18446744073709551616",
    "7",
    "8",
    "9",
    "10",
    "100",
    "1000000",
    ".",
    "-.",
    "1.",
    ".5",
    "1..2",
    "1-2",
    "--1",
    "+1",
];

/// G and M numbers, read and unread.
const CODES: &[&str] = &[
    "G0",
    "G1",
    "G2",
    "G3",
    "G4",
    "G5",
    "G5.1",
    "G5.2",
    "G5.3",
    "G6.2",
    "G6",
    "G6.1",
    "G6.3",
    "G7",
    "G8",
    "G10",
    "G15",
    "G16",
    "G17",
    "G17.1",
    "G18",
    "G19",
    "G20",
    "G21",
    "G28",
    "G28.1",
    "G30",
    "G33",
    "G33.1",
    "G38.2",
    "G38.5",
    "G40",
    "G41",
    "G41.1",
    "G42",
    "G43",
    "G43.1",
    "G49",
    "G50",
    "G51",
    "G52",
    "G53",
    "G54",
    "G59.3",
    "G61",
    "G61.1",
    "G64",
    "G68",
    "G69",
    "G70",
    "G71",
    "G73",
    "G76",
    "G80",
    "G81",
    "G89",
    "G90",
    "G90.1",
    "G91",
    "G91.1",
    "G92",
    "G92.1",
    "G92.3",
    "G93",
    "G94",
    "G95",
    "G96",
    "G97",
    "G98",
    "G99",
    "G999",
    "G1.5",
    "M0",
    "M1",
    "M2",
    "M3",
    "M5",
    "M6",
    "M8",
    "M30",
    "M60",
    "M62 P1",
    "M66 P0 L0",
    "M98 P100",
    "M99",
    "M100",
    "M199",
    "M1000",
];

const WORDS: &[u8] = b"XYZIJKRPQLFABCUVWENSTDHO";

/// Random mutations of `text` (one half the time, two a quarter, ... up
/// to six: single mutations keep most programs readable, so the smoother
/// and writers see them too); `others` are texts to splice pieces from.
pub fn mutate_bytes(rng: &mut Rng, text: &[u8], others: &[Vec<u8>]) -> Vec<u8> {
    let mut out = text.to_vec();
    let mut n = 1;
    while n < 6 && rng.one_in(2) {
        n += 1;
    }
    for _ in 0..n {
        mutate_once(rng, &mut out, others);
    }
    out
}

fn mutate_once(rng: &mut Rng, t: &mut Vec<u8>, others: &[Vec<u8>]) {
    let pos = |rng: &mut Rng, t: &Vec<u8>| rng.below(t.len() + 1);
    match rng.below(17) {
        0 if !t.is_empty() => {
            let i = rng.below(t.len());
            t[i] ^= 1 << rng.below(8);
        }
        1 if !t.is_empty() => {
            let i = rng.below(t.len());
            t[i] = b" \n-.0123456789GXYZIJKRPF#[]()%/;"[rng.below(32)];
        }
        2 => {
            let i = pos(rng, t);
            let tok = rng.pick(TOKENS).as_bytes();
            t.splice(i..i, tok.iter().copied());
        }
        3 if !t.is_empty() => {
            let i = rng.below(t.len());
            let n = (1 + rng.below(16)).min(t.len() - i);
            t.drain(i..i + n);
        }
        4 => edit_lines(rng, t, |rng, lines| {
            let i = rng.below(lines.len());
            lines.remove(i);
        }),
        5 => edit_lines(rng, t, |rng, lines| {
            let i = rng.below(lines.len());
            let l = lines[i].clone();
            for _ in 0..1 + rng.below(3) {
                lines.insert(i, l.clone());
            }
        }),
        6 => edit_lines(rng, t, |rng, lines| {
            let (i, j) = (rng.below(lines.len()), rng.below(lines.len()));
            lines.swap(i, j);
        }),
        7 => {
            let n = rng.pick(NUMBERS).as_bytes().to_vec();
            replace_number(rng, t, n);
        }
        14 | 15 => {
            // A plausible value: the program stays readable, its geometry
            // changes (tiny moves, reversals, spikes).
            let digits = rng.below(7);
            let v = (rng.unit() - 0.5) * [0.002, 2.0, 200.0, 2e4][rng.below(4)];
            let n = format!("{v:.digits$}").into_bytes();
            replace_number(rng, t, n);
        }
        16 => {
            // Another number of the same text: repeated points, zero-length
            // and reversed moves.
            if let Some(n) = some_number(rng, t) {
                replace_number(rng, t, n);
            }
        }
        8 => {
            // A code as a word of its own: at a line start or after a space.
            let i = pos(rng, t);
            let mut code = rng.pick(CODES).as_bytes().to_vec();
            code.insert(0, if rng.one_in(2) { b'\n' } else { b' ' });
            code.push(b' ');
            t.splice(i..i, code);
        }
        9 => {
            let i = pos(rng, t);
            let word = format!(
                " {}{} ",
                WORDS[rng.below(WORDS.len())] as char,
                rng.pick(NUMBERS)
            );
            t.splice(i..i, word.bytes());
        }
        10 if !t.is_empty() => {
            let n = rng.below(t.len());
            t.truncate(n);
        }
        11 if !others.is_empty() => {
            let o = rng.pick(others);
            if !o.is_empty() {
                let a = rng.below(o.len());
                let b = (a + 1 + rng.below(200)).min(o.len());
                let i = pos(rng, t);
                t.splice(i..i, o[a..b].iter().copied());
            }
        }
        12 => {
            // A very long digit string.
            let i = pos(rng, t);
            let n = 20 + rng.below(400);
            let digits: Vec<u8> = (0..n).map(|_| b'0' + rng.below(10) as u8).collect();
            t.splice(i..i, digits);
        }
        _ => {
            // Invalid UTF-8 or control bytes.
            let i = pos(rng, t);
            let b = *rng.pick(&[0u8, 0x80, 0xff, 0xc3, 0x0b, 0x0c, 0x1b, b'\r']);
            t.insert(i, b);
        }
    }
}

fn edit_lines(rng: &mut Rng, t: &mut Vec<u8>, f: impl FnOnce(&mut Rng, &mut Vec<Vec<u8>>)) {
    let mut lines: Vec<Vec<u8>> = t.split(|&b| b == b'\n').map(|l| l.to_vec()).collect();
    f(rng, &mut lines);
    *t = lines.join(&b'\n');
}

/// The byte range of a random number (a run of digits, `.`, signs and
/// `e`) of `t`.
fn number_at(rng: &mut Rng, t: &[u8]) -> Option<(usize, usize)> {
    let starts: Vec<usize> = (0..t.len())
        .filter(|&i| t[i].is_ascii_digit() && (i == 0 || !t[i - 1].is_ascii_digit()))
        .collect();
    if starts.is_empty() {
        return None;
    }
    let mut a = *rng.pick(&starts);
    while a > 0 && matches!(t[a - 1], b'-' | b'+' | b'.') {
        a -= 1;
    }
    let mut b = a;
    while b < t.len() && matches!(t[b], b'0'..=b'9' | b'.' | b'-' | b'+' | b'e') {
        b += 1;
    }
    Some((a, b))
}

/// A copy of a random number of `t`.
fn some_number(rng: &mut Rng, t: &[u8]) -> Option<Vec<u8>> {
    number_at(rng, t).map(|(a, b)| t[a..b].to_vec())
}

/// Replaces a random number of `t` by `n`.
fn replace_number(rng: &mut Rng, t: &mut Vec<u8>, n: Vec<u8>) {
    if let Some((a, b)) = number_at(rng, t) {
        t.splice(a..b, n);
    }
}

/// A mutation of a JSON pieces document: structural changes of one piece
/// (degree, knots, points, weights, type, source lines, feed) or of the
/// document, and sometimes byte mutations of the text on top.
pub fn mutate_json(rng: &mut Rng, text: &str) -> Vec<u8> {
    let Ok(mut doc) = serde_json::from_str::<Value>(text) else {
        return text.as_bytes().to_vec();
    };
    for _ in 0..1 + rng.below(3) {
        mutate_doc(rng, &mut doc);
    }
    let mut out = serde_json::to_string(&doc).unwrap_or_default().into_bytes();
    if rng.one_in(4) {
        out = mutate_bytes(rng, &out, &[]);
    }
    out
}

fn interesting_f64(rng: &mut Rng) -> Value {
    let v = *rng.pick(&[
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.5,
        1e308,
        -1e308,
        f64::MAX,
        f64::MIN_POSITIVE,
        5e-324,
        1e-12,
        1e12,
        3.0,
        9.0,
    ]);
    if rng.one_in(3) {
        json!(rng.unit() * 20.0 - 10.0)
    } else {
        json!(v)
    }
}

fn mutate_doc(rng: &mut Rng, doc: &mut Value) {
    if rng.one_in(20) {
        doc["units"] = json!(*rng.pick(&["inch", "MM", "", "mm"]));
        return;
    }
    let Some(pieces) = doc.get_mut("pieces").and_then(Value::as_array_mut) else {
        return;
    };
    if pieces.is_empty() {
        return;
    }
    if rng.one_in(10) {
        // Whole pieces removed, duplicated or swapped.
        let (i, j) = (rng.below(pieces.len()), rng.below(pieces.len()));
        match rng.below(3) {
            0 => {
                pieces.remove(i);
            }
            1 => {
                let p = pieces[i].clone();
                pieces.insert(j, p);
            }
            _ => pieces.swap(i, j),
        }
        return;
    }
    let nurbs: Vec<usize> = (0..pieces.len())
        .filter(|&i| pieces[i]["type"] == "nurbs")
        .collect();
    let i = if !nurbs.is_empty() && !rng.one_in(4) {
        *rng.pick(&nurbs)
    } else {
        rng.below(pieces.len())
    };
    let p = &mut pieces[i];
    match rng.below(12) {
        0 | 1 => {
            p["degree"] = json!(*rng.pick(&[0usize, 1, 2, 3, 4, 5, 7, 8, 9, 10, 12, 40, 1 << 20]))
        }
        2 => {
            // The degree changed with the knots kept consistent.
            let d = 1 + rng.below(10);
            let n = p["points"].as_array().map_or(0, Vec::len);
            p["degree"] = json!(d);
            let mut k = vec![0.0; d + 1];
            for j in 1..n.saturating_sub(d) {
                k.push(j as f64);
            }
            k.extend(vec![n.saturating_sub(d) as f64; d + 1]);
            p["knots"] = json!(k);
        }
        3 => edit_array(rng, &mut p["knots"], interesting_f64),
        4 => edit_array(rng, &mut p["points"], |rng| {
            json!([
                interesting_f64(rng),
                interesting_f64(rng),
                interesting_f64(rng)
            ])
        }),
        5 => {
            let n = p["points"].as_array().map_or(0, Vec::len);
            p["weights"] = match rng.below(4) {
                0 => Value::Null,
                1 => json!(vec![1.0; n + rng.below(3)]),
                _ => json!((0..n).map(|_| interesting_f64(rng)).collect::<Vec<_>>()),
            };
        }
        6 if p["weights"].is_array() => edit_array(rng, &mut p["weights"], interesting_f64),
        7 => {
            p["type"] = json!(if p["type"] == "line" { "nurbs" } else { "line" });
        }
        8 => {
            let a = rng.below(40);
            p["source_lines"] = json!([a, if rng.one_in(2) { a } else { rng.below(40) }]);
        }
        9 => p["feed"] = interesting_f64(rng),
        10 => p["rapid"] = json!(rng.one_in(2)),
        _ => {
            let key = *rng.pick(&["p0", "p1"]);
            p[key] = json!([
                interesting_f64(rng),
                interesting_f64(rng),
                interesting_f64(rng)
            ]);
        }
    }
}

/// Changes, removes, appends or shuffles an element of a JSON array.
fn edit_array(rng: &mut Rng, a: &mut Value, mut make: impl FnMut(&mut Rng) -> Value) {
    let Some(items) = a.as_array_mut() else {
        return;
    };
    match rng.below(4) {
        0 if !items.is_empty() => {
            let i = rng.below(items.len());
            items[i] = make(rng);
        }
        1 if !items.is_empty() => {
            let i = rng.below(items.len());
            items.remove(i);
        }
        2 => {
            let i = rng.below(items.len() + 1);
            items.insert(i, make(rng));
        }
        _ if items.len() > 1 => {
            let (i, j) = (rng.below(items.len()), rng.below(items.len()));
            items.swap(i, j);
        }
        _ => {}
    }
}
