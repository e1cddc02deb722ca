//! A colour as the SVG writes it: 8-bit sRGB channels, `rgb(r,g,b)`.

/// An sRGB colour, 8 bits a channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Rgb(pub u8, pub u8, pub u8);
