//! The numerical conventions the code relies on, numbered; the code and the tests cite
//! them by number. The text is `docs/conventions.md`.
#![doc = include_str!("../docs/conventions.md")]
