//! Pixel-space geometry shared by the legend placement and its checker:
//! rectangles against circles, segments and rectangles.

/// An axis-aligned rectangle in SVG pixels (y grows downwards).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

/// Something drawn that a legend must not cover.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    Circle { cx: f64, cy: f64, r: f64 },
    Segment { a: (f64, f64), b: (f64, f64) },
    Box(Rect),
}

impl Rect {
    pub fn new(x: f64, y: f64, w: f64, h: f64) -> Self {
        Self {
            x0: x,
            y0: y,
            x1: x + w,
            y1: y + h,
        }
    }

    pub fn width(&self) -> f64 {
        self.x1 - self.x0
    }

    pub fn height(&self) -> f64 {
        self.y1 - self.y0
    }

    pub fn inflate(&self, m: f64) -> Self {
        Self {
            x0: self.x0 - m,
            y0: self.y0 - m,
            x1: self.x1 + m,
            y1: self.y1 + m,
        }
    }

    pub fn overlaps(&self, o: &Rect) -> bool {
        self.x0 <= o.x1 && o.x0 <= self.x1 && self.y0 <= o.y1 && o.y0 <= self.y1
    }

    /// Whether the segment a-b enters the rectangle (Liang-Barsky clipping).
    pub fn meets_segment(&self, a: (f64, f64), b: (f64, f64)) -> bool {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
        for (p, q) in [
            (-dx, a.0 - self.x0),
            (dx, self.x1 - a.0),
            (-dy, a.1 - self.y0),
            (dy, self.y1 - a.1),
        ] {
            if p == 0.0 {
                if q < 0.0 {
                    return false;
                }
            } else {
                let t = q / p;
                if p < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
                if t0 > t1 {
                    return false;
                }
            }
        }
        true
    }

    pub fn meets_circle(&self, cx: f64, cy: f64, r: f64) -> bool {
        let nx = cx.clamp(self.x0, self.x1);
        let ny = cy.clamp(self.y0, self.y1);
        (nx - cx).powi(2) + (ny - cy).powi(2) <= r * r
    }

    pub fn meets(&self, s: &Shape) -> bool {
        match *s {
            Shape::Circle { cx, cy, r } => self.meets_circle(cx, cy, r),
            Shape::Segment { a, b } => self.meets_segment(a, b),
            Shape::Box(r) => self.overlaps(&r),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_crossing_without_a_vertex_inside_are_caught() {
        let r = Rect::new(10.0, 10.0, 10.0, 10.0);
        assert!(r.meets_segment((0.0, 15.0), (30.0, 15.0)));
        assert!(r.meets_segment((12.0, 12.0), (13.0, 13.0)));
        assert!(!r.meets_segment((0.0, 0.0), (30.0, 5.0)));
        assert!(!r.meets_segment((0.0, 25.0), (25.0, 40.0)));
        assert!(r.meets_segment((15.0, 0.0), (15.0, 30.0)));
    }

    #[test]
    fn circles_touching_a_corner() {
        let r = Rect::new(10.0, 10.0, 10.0, 10.0);
        assert!(r.meets_circle(22.0, 22.0, 3.0));
        assert!(!r.meets_circle(23.0, 23.0, 3.0));
    }
}
