#pragma once
// Internal: an RGB image and the anti-aliased primitives the video frames are
// drawn with (shaded discs, lines, filled convex polygons), in pixel
// coordinates with y downwards.

#include <array>
#include <cstdint>
#include <vector>

namespace lagrangian::view::detail {

struct Rgb {
  double r = 0, g = 0, b = 0;  // 0..1
};

Rgb rgb(int hex);

class Image {
 public:
  Image(int width, int height, Rgb background);
  int width() const { return w_; }
  int height() const { return h_; }
  /// Blends colour c into pixel (x, y) with coverage a in [0, 1].
  void blend(int x, int y, Rgb c, double a);
  /// A disc of radius r centred at (cx, cy), shaded as a sphere lit from the viewer.
  void sphere(double cx, double cy, double r, Rgb c);
  /// A circle's outline of radius r, `width` px wide.
  void ring(double cx, double cy, double r, double width, Rgb c, double alpha = 1);
  /// A segment `width` px wide.
  void line(double x0, double y0, double x1, double y1, double width, Rgb c, double alpha = 1);
  /// A filled convex polygon.
  void polygon(const std::vector<std::array<double, 2>>& corners, Rgb c, double alpha = 1);
  /// Binary PPM (P6), as ffmpeg reads from a pipe.
  void write_ppm(std::vector<std::uint8_t>& out) const;

 private:
  int w_, h_;
  std::vector<Rgb> px_;
};

}  // namespace lagrangian::view::detail
