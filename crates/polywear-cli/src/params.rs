//! `polywear params`: every model parameter with unit, default, provenance, accepted range and
//! plausible range, and the wear stage's category settings (wear zone, wear power); the table
//! is `polywear_core::params::table`'s.

use polywear_core::params::table::{markdown_table, text_table};

pub(crate) fn run(markdown: bool) {
    match markdown {
        true => print!("{}", markdown_table()),
        false => print!("{}", text_table()),
    }
}
