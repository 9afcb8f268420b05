//! The shared look of every figure, in layers, each importing only the ones below it:
//!
//! 1. [`palette`] and [`number`] (the bottom: colours and dashes; numbers as text),
//! 2. [`text`] (fonts, measured and wrapped text, the title block, the one title helper),
//! 3. [`axes`] (charts, their frame, chart units to pixels),
//! 4. [`marks`] (markers, fills, paths, bands, the cursor, hatching),
//! 5. [`legend`] (entries, swatches and their layout),
//! 6. [`notes`] (framed notes in the emptiest corner).
//!
//! Panels import them through this module (`style::legend(…)`, `style::KF`).

pub mod axes;
pub mod legend;
pub mod marks;
pub mod notes;
pub mod number;
pub mod palette;
pub mod text;

pub use axes::*;
pub use legend::*;
pub use marks::*;
pub use notes::*;
pub use number::*;
pub use palette::*;
pub use text::*;
