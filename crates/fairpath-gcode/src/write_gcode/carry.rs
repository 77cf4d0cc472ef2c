//! What the lines a smoothed run replaces carry besides their moves: N
//! numbers and comments, written back beside the blocks that replace them.

/// Longest comment line written for merged N numbers (characters):
/// LinuxCNC refuses lines longer than 255 characters (`LINELEN`,
/// interp_internal.hh); Fanuc and Haas show lines of about 80 columns.
pub const MAX_COMMENT_CHARS: usize = 72;

/// The comments of a line as written (`( ... )` in order, then a `; ...`
/// to the end of the line), for a line the lexer read: its parentheses
/// close on the line and a `;` outside them starts a comment to the end.
pub fn comments_of(text: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut open: Option<usize> = None;
    for (i, c) in text.char_indices() {
        match (open, c) {
            (None, '(') => open = Some(i),
            (Some(s), ')') => {
                out.push(&text[s..=i]);
                open = None;
            }
            (None, ';') => {
                out.push(text[i..].trim_end());
                break;
            }
            _ => {}
        }
    }
    out
}

/// The N word of a line (`N0020` as written, upper case).
pub fn n_word(words: &[crate::lexer::Word]) -> Option<String> {
    words
        .iter()
        .find(|w| w.letter == 'N')
        .map(|w| format!("N{}", w.text))
}

/// Comment lines naming the N words `ns` (in program order) whose lines
/// were merged into `what` (`"the next block"`): increasing stretches are
/// written `N30-N50` (the lines numbered N30 to N50), single ones `N30`,
/// wrapped so that no line exceeds [`MAX_COMMENT_CHARS`].
pub fn merged_n_comments(ns: &[(String, f64)], what: &str) -> Vec<String> {
    let mut items: Vec<String> = Vec::new();
    let mut k = 0;
    while k < ns.len() {
        let mut e = k;
        while e + 1 < ns.len() && ns[e + 1].1 > ns[e].1 {
            e += 1;
        }
        items.push(match e - k {
            0 => ns[k].0.clone(),
            1 => format!("{} {}", ns[k].0, ns[e].0),
            _ => format!("{}-{}", ns[k].0, ns[e].0),
        });
        k = e + 1;
    }
    let tail = format!(" merged into {what})");
    let mut lines = Vec::new();
    let mut cur = String::from("(");
    for it in items {
        if cur.len() > 1 && cur.len() + 1 + it.len() + tail.len() > MAX_COMMENT_CHARS {
            lines.push(cur + &tail);
            cur = String::from("(");
        }
        if cur.len() > 1 {
            cur.push(' ');
        }
        cur.push_str(&it);
    }
    if cur.len() > 1 {
        lines.push(cur + &tail);
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_are_found_as_written() {
        assert_eq!(
            comments_of("N10 G1 X1 (corner 3) Y2 (a;b) ; rest (x)  "),
            ["(corner 3)", "(a;b)", "; rest (x)"]
        );
        assert!(comments_of("G1 X1").is_empty());
        assert_eq!(comments_of("(MSG, hello)"), ["(MSG, hello)"]);
    }

    #[test]
    fn merged_n_numbers_are_compressed_into_stretches_and_wrapped() {
        let ns: Vec<(String, f64)> = [30, 40, 50, 60, 10, 20, 5]
            .iter()
            .map(|&n| (format!("N{n}"), n as f64))
            .collect();
        assert_eq!(
            merged_n_comments(&ns, "the next block"),
            ["(N30-N60 N10 N20 N5 merged into the next block)"]
        );
        // Decreasing numbers: one item each, wrapped.
        let ns: Vec<(String, f64)> = (0..40)
            .rev()
            .map(|n| (format!("N{}", 1000 + n), (1000 + n) as f64))
            .collect();
        let lines = merged_n_comments(&ns, "the next block");
        assert!(lines.len() > 1);
        let mut all = String::new();
        for l in &lines {
            assert!(l.len() <= MAX_COMMENT_CHARS, "{l}");
            all.push_str(l);
        }
        for (n, _) in &ns {
            assert!(all.contains(n.as_str()), "{n}");
        }
    }
}
