// Anti-aliased drawing into an RGB image: coverage from the distance to each
// shape's edge, one pixel wide.

#include "raster.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace lagrangian::view::detail {

Rgb rgb(int hex) { return {((hex >> 16) & 255) / 255.0, ((hex >> 8) & 255) / 255.0, (hex & 255) / 255.0}; }

Image::Image(int width, int height, Rgb background)
    : w_(width), h_(height), px_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), background) {}

void Image::blend(int x, int y, Rgb c, double a) {
  if (x < 0 || y < 0 || x >= w_ || y >= h_ || !(a > 0)) return;
  a = std::min(a, 1.0);
  Rgb& p = px_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(x)];
  p.r += (c.r - p.r) * a;
  p.g += (c.g - p.g) * a;
  p.b += (c.b - p.b) * a;
}

namespace {
double clamp01(double v) { return std::clamp(v, 0.0, 1.0); }
struct Box {
  int x0, y0, x1, y1;
};
Box bounds(double xmin, double ymin, double xmax, double ymax, int w, int h) {
  return {std::max(0, static_cast<int>(std::floor(xmin))), std::max(0, static_cast<int>(std::floor(ymin))),
          std::min(w - 1, static_cast<int>(std::ceil(xmax))), std::min(h - 1, static_cast<int>(std::ceil(ymax)))};
}
}  // namespace

void Image::sphere(double cx, double cy, double r, Rgb c) {
  r = std::max(r, 1.0);
  const Box b = bounds(cx - r - 1, cy - r - 1, cx + r + 1, cy + r + 1, w_, h_);
  for (int y = b.y0; y <= b.y1; ++y)
    for (int x = b.x0; x <= b.x1; ++x) {
      const double dx = x + 0.5 - cx, dy = y + 0.5 - cy, d = std::hypot(dx, dy);
      const double cover = clamp01(r + 0.5 - d);
      if (cover <= 0) continue;
      // Lambert shading under a light slightly above and left of the viewer.
      const double u = std::min(d / r, 1.0), nz = std::sqrt(1 - u * u);
      const double nx = dx / r, ny = dy / r;
      const double light = 0.55 + 0.45 * clamp01(0.85 * nz - 0.3 * nx - 0.4 * ny);
      blend(x, y, {c.r * light, c.g * light, c.b * light}, cover);
    }
}

void Image::ring(double cx, double cy, double r, double width, Rgb c, double alpha) {
  const double half = width / 2;
  const Box b = bounds(cx - r - half - 1, cy - r - half - 1, cx + r + half + 1, cy + r + half + 1, w_, h_);
  for (int y = b.y0; y <= b.y1; ++y)
    for (int x = b.x0; x <= b.x1; ++x) {
      const double d = std::abs(std::hypot(x + 0.5 - cx, y + 0.5 - cy) - r);
      blend(x, y, c, alpha * clamp01(half + 0.5 - d));
    }
}

void Image::line(double x0, double y0, double x1, double y1, double width, Rgb c, double alpha) {
  const double half = width / 2;
  const double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
  const Box b = bounds(std::min(x0, x1) - half - 1, std::min(y0, y1) - half - 1, std::max(x0, x1) + half + 1,
                       std::max(y0, y1) + half + 1, w_, h_);
  for (int y = b.y0; y <= b.y1; ++y)
    for (int x = b.x0; x <= b.x1; ++x) {
      const double px = x + 0.5 - x0, py = y + 0.5 - y0;
      const double s = len2 > 0 ? clamp01((px * dx + py * dy) / len2) : 0.0;
      const double d = std::hypot(px - s * dx, py - s * dy);
      blend(x, y, c, alpha * clamp01(half + 0.5 - d));
    }
}

void Image::polygon(const std::vector<std::array<double, 2>>& p, Rgb c, double alpha) {
  if (p.size() < 3) return;
  double xmin = p[0][0], xmax = xmin, ymin = p[0][1], ymax = ymin;
  for (const auto& q : p) {
    xmin = std::min(xmin, q[0]);
    xmax = std::max(xmax, q[0]);
    ymin = std::min(ymin, q[1]);
    ymax = std::max(ymax, q[1]);
  }
  // orientation, so that "inside" is on the same side of every edge
  double area = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& a = p[i];
    const auto& b = p[(i + 1) % p.size()];
    area += a[0] * b[1] - b[0] * a[1];
  }
  const double sign = area >= 0 ? 1.0 : -1.0;
  const Box b = bounds(xmin - 1, ymin - 1, xmax + 1, ymax + 1, w_, h_);
  for (int y = b.y0; y <= b.y1; ++y)
    for (int x = b.x0; x <= b.x1; ++x) {
      double inside = 1e300;  // signed distance to the nearest edge, positive inside
      for (std::size_t i = 0; i < p.size(); ++i) {
        const auto& a = p[i];
        const auto& e = p[(i + 1) % p.size()];
        const double ex = e[0] - a[0], ey = e[1] - a[1], len = std::hypot(ex, ey);
        if (len == 0) continue;
        inside = std::min(inside, sign * (ex * (y + 0.5 - a[1]) - ey * (x + 0.5 - a[0])) / len);
      }
      blend(x, y, c, alpha * clamp01(inside + 0.5));
    }
}

void Image::write_ppm(std::vector<std::uint8_t>& out) const {
  const std::string header = "P6\n" + std::to_string(w_) + " " + std::to_string(h_) + "\n255\n";
  out.assign(header.begin(), header.end());
  out.reserve(out.size() + px_.size() * 3);
  for (const Rgb& p : px_)
    for (const double v : {p.r, p.g, p.b}) out.push_back(static_cast<std::uint8_t>(std::lround(255 * clamp01(v))));
}

}  // namespace lagrangian::view::detail
