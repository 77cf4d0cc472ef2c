//! A short string kept inline: the number of a G-code word as written
//! (`12.3456`, `-0.0005`) fits in [`INLINE`] bytes, so a program's words
//! and the written end coordinates of its moves take no allocation of
//! their own (on a long program, a great many small heap blocks;
//! measurements: docs/tuning.md, `ShortText`). Longer texts (an
//! expression's literal, a long number) go to the heap.

use core::fmt;
use core::ops::Deref;

/// Bytes held inline.
pub const INLINE: usize = 22;

/// A string of any length, inline up to [`INLINE`] bytes. Derefs to `str`.
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct ShortText(Repr);

#[derive(Clone, PartialEq, Eq, Hash)]
enum Repr {
    /// `bytes[..len]` is the text (valid UTF-8); the rest is zero, so that
    /// equal texts are equal values.
    Inline {
        len: u8,
        bytes: [u8; INLINE],
    },
    Heap(Box<str>),
}

impl ShortText {
    pub fn new(s: &str) -> ShortText {
        if s.len() <= INLINE {
            let mut bytes = [0u8; INLINE];
            bytes[..s.len()].copy_from_slice(s.as_bytes());
            ShortText(Repr::Inline {
                len: s.len() as u8,
                bytes,
            })
        } else {
            ShortText(Repr::Heap(s.into()))
        }
    }

    pub fn as_str(&self) -> &str {
        match &self.0 {
            Repr::Inline { len, bytes } => core::str::from_utf8(&bytes[..*len as usize])
                .expect("built from a str, cut at its length"),
            Repr::Heap(s) => s,
        }
    }
}

impl Default for ShortText {
    fn default() -> Self {
        ShortText::new("")
    }
}

impl Deref for ShortText {
    type Target = str;
    fn deref(&self) -> &str {
        self.as_str()
    }
}

impl AsRef<str> for ShortText {
    fn as_ref(&self) -> &str {
        self.as_str()
    }
}

impl From<&str> for ShortText {
    fn from(s: &str) -> Self {
        ShortText::new(s)
    }
}

impl From<String> for ShortText {
    fn from(s: String) -> Self {
        ShortText::new(&s)
    }
}

impl From<&String> for ShortText {
    fn from(s: &String) -> Self {
        ShortText::new(s)
    }
}

impl From<ShortText> for String {
    fn from(s: ShortText) -> Self {
        s.as_str().to_string()
    }
}

impl PartialEq<str> for ShortText {
    fn eq(&self, o: &str) -> bool {
        self.as_str() == o
    }
}

impl PartialEq<&str> for ShortText {
    fn eq(&self, o: &&str) -> bool {
        self.as_str() == *o
    }
}

impl PartialEq<String> for ShortText {
    fn eq(&self, o: &String) -> bool {
        self.as_str() == o.as_str()
    }
}

impl fmt::Debug for ShortText {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self.as_str(), f)
    }
}

impl fmt::Display for ShortText {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self.as_str(), f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn it_is_as_small_as_a_string_and_so_is_an_option_of_it() {
        assert_eq!(core::mem::size_of::<ShortText>(), 24);
        assert_eq!(core::mem::size_of::<Option<ShortText>>(), 24);
    }

    proptest! {
        #[test]
        fn it_holds_any_text_and_compares_as_it(a in ".{0,40}", b in ".{0,40}") {
            let (x, y) = (ShortText::new(&a), ShortText::new(&b));
            prop_assert_eq!(x.as_str(), a.as_str());
            prop_assert_eq!(x == y, a == b);
            prop_assert_eq!(format!("{x:?}"), format!("{a:?}"));
            prop_assert_eq!(String::from(x.clone()), a.clone());
            prop_assert!(x == a.as_str());
        }
    }
}
