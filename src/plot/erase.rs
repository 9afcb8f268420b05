//! One backend type for all the drawing code.
//!
//! `plot::draw` is generic over plotters' `DrawingBackend`, but every panel, and plotters'
//! chart machinery under it, is instantiated once only: for [`Erased`], which forwards each
//! primitive through an object-safe trait to the real backend. Without this, every backend the
//! crate draws on (the browser canvas and SVG export in wasm) got its own copy of all figure
//! code, which cost about 100 KB of gzipped wasm.

use crate::error::Error;
use plotters::drawing::DrawingAreaErrorKind;
use plotters::prelude::*;
use plotters::style::{FontDesc, FontFamily};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind,
};
use std::fmt;

/// A backend error as text (the drawing code only reports it).
#[derive(Debug, Clone)]
pub struct ErasedError(pub String);

impl fmt::Display for ErasedError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ErasedError {}

type Res<T> = Result<T, DrawingErrorKind<ErasedError>>;

/// A solid color and width: everything a shape style says to a backend.
#[derive(Clone, Copy)]
pub struct Stroke {
    color: BackendColor,
    width: u32,
}

impl BackendStyle for Stroke {
    fn color(&self) -> BackendColor {
        self.color
    }
    fn stroke_width(&self) -> u32 {
        self.width
    }
}

fn stroke<S: BackendStyle>(s: &S) -> Stroke {
    Stroke {
        color: s.color(),
        width: s.stroke_width(),
    }
}

/// A text style in plotters' concrete type (families reduced to the three generic ones).
fn text_style<S: BackendTextStyle>(s: &S) -> TextStyle<'static> {
    let family = match s.family().as_str() {
        "serif" => FontFamily::Serif,
        "monospace" => FontFamily::Monospace,
        _ => FontFamily::SansSerif,
    };
    let mut t =
        TextStyle::from(FontDesc::new(family, s.size(), s.style()).transform(s.transform()));
    t.color = s.color();
    t.pos = s.anchor();
    t
}

/// The object-safe part of a drawing backend.
pub trait Sink {
    fn size(&self) -> (u32, u32);
    fn prepare(&mut self) -> Res<()>;
    fn present(&mut self) -> Res<()>;
    fn pixel(&mut self, p: BackendCoord, c: BackendColor) -> Res<()>;
    fn line(&mut self, a: BackendCoord, b: BackendCoord, s: Stroke) -> Res<()>;
    fn rect(&mut self, a: BackendCoord, b: BackendCoord, s: Stroke, fill: bool) -> Res<()>;
    fn path(&mut self, pts: Vec<BackendCoord>, s: Stroke) -> Res<()>;
    fn circle(&mut self, c: BackendCoord, r: u32, s: Stroke, fill: bool) -> Res<()>;
    fn polygon(&mut self, pts: Vec<BackendCoord>, s: Stroke) -> Res<()>;
    fn text(&mut self, text: &str, s: &TextStyle<'static>, p: BackendCoord) -> Res<()>;
    fn text_size(&self, text: &str, s: &TextStyle<'static>) -> Res<(u32, u32)>;
}

/// A real backend behind [`Sink`].
pub struct Adapter<DB>(pub DB);

fn erase<E: std::error::Error + Send + Sync>(
    e: DrawingErrorKind<E>,
) -> DrawingErrorKind<ErasedError> {
    match e {
        DrawingErrorKind::DrawingError(e) => {
            DrawingErrorKind::DrawingError(ErasedError(e.to_string()))
        }
        DrawingErrorKind::FontError(f) => DrawingErrorKind::FontError(f),
    }
}

impl<DB: DrawingBackend> Sink for Adapter<DB> {
    fn size(&self) -> (u32, u32) {
        self.0.get_size()
    }
    fn prepare(&mut self) -> Res<()> {
        self.0.ensure_prepared().map_err(erase)
    }
    fn present(&mut self) -> Res<()> {
        self.0.present().map_err(erase)
    }
    fn pixel(&mut self, p: BackendCoord, c: BackendColor) -> Res<()> {
        self.0.draw_pixel(p, c).map_err(erase)
    }
    fn line(&mut self, a: BackendCoord, b: BackendCoord, s: Stroke) -> Res<()> {
        self.0.draw_line(a, b, &s).map_err(erase)
    }
    fn rect(&mut self, a: BackendCoord, b: BackendCoord, s: Stroke, fill: bool) -> Res<()> {
        self.0.draw_rect(a, b, &s, fill).map_err(erase)
    }
    fn path(&mut self, pts: Vec<BackendCoord>, s: Stroke) -> Res<()> {
        self.0.draw_path(pts, &s).map_err(erase)
    }
    fn circle(&mut self, c: BackendCoord, r: u32, s: Stroke, fill: bool) -> Res<()> {
        self.0.draw_circle(c, r, &s, fill).map_err(erase)
    }
    fn polygon(&mut self, pts: Vec<BackendCoord>, s: Stroke) -> Res<()> {
        self.0.fill_polygon(pts, &s).map_err(erase)
    }
    fn text(&mut self, text: &str, s: &TextStyle<'static>, p: BackendCoord) -> Res<()> {
        self.0.draw_text(text, s, p).map_err(erase)
    }
    fn text_size(&self, text: &str, s: &TextStyle<'static>) -> Res<(u32, u32)> {
        self.0.estimate_text_size(text, s).map_err(erase)
    }
}

/// The one backend type the figure code is compiled for.
pub struct Erased<'a>(pub &'a mut dyn Sink);

impl DrawingBackend for Erased<'_> {
    type ErrorType = ErasedError;

    fn get_size(&self) -> (u32, u32) {
        self.0.size()
    }
    fn ensure_prepared(&mut self) -> Res<()> {
        self.0.prepare()
    }
    fn present(&mut self) -> Res<()> {
        self.0.present()
    }
    fn draw_pixel(&mut self, p: BackendCoord, c: BackendColor) -> Res<()> {
        self.0.pixel(p, c)
    }
    fn draw_line<S: BackendStyle>(&mut self, a: BackendCoord, b: BackendCoord, s: &S) -> Res<()> {
        self.0.line(a, b, stroke(s))
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        a: BackendCoord,
        b: BackendCoord,
        s: &S,
        fill: bool,
    ) -> Res<()> {
        self.0.rect(a, b, stroke(s), fill)
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        s: &S,
    ) -> Res<()> {
        self.0.path(path.into_iter().collect(), stroke(s))
    }
    fn draw_circle<S: BackendStyle>(
        &mut self,
        c: BackendCoord,
        r: u32,
        s: &S,
        fill: bool,
    ) -> Res<()> {
        self.0.circle(c, r, stroke(s), fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        s: &S,
    ) -> Res<()> {
        self.0.polygon(vert.into_iter().collect(), stroke(s))
    }
    fn draw_text<S: BackendTextStyle>(&mut self, text: &str, s: &S, p: BackendCoord) -> Res<()> {
        self.0.text(text, &text_style(s), p)
    }
    fn estimate_text_size<S: BackendTextStyle>(&self, text: &str, s: &S) -> Res<(u32, u32)> {
        self.0.text_size(text, &text_style(s))
    }
}

/// A drawing error as a crate error.
pub(crate) fn de<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> Error {
    Error::field("figure", format!("could not be drawn: {e}"))
}
