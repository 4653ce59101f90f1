// A run as a video: the figure's frames drawn in software (an orthographic
// view from the page's opening direction) and encoded by ffmpeg from a pipe.

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "check.hpp"
#include "lagrangian/view/view.hpp"
#include "raster.hpp"

namespace lagrangian::view {
namespace {

namespace fs = std::filesystem;
using detail::Image;
using detail::Rgb;

constexpr int kPalette[] = {0xd62728, 0x1f77b4, 0x2ca02c, 0xff7f0e, 0x9467bd, 0x8c564b, 0xe377c2, 0x17becf, 0xbcbd22};

struct V3 {
  double x = 0, y = 0, z = 0;
};
V3 v3(const Point& p) { return {p[0], p[1], p[2]}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 unit(V3 a) {
  const double n = std::sqrt(dot(a, a));
  return n > 0 ? (1.0 / n) * a : V3{0, 0, 1};
}
double& at(V3& v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

/// The view: screen axes `right`, `up` and the direction towards the viewer,
/// and the scale and offset that fit the scene into the frame.
struct Camera {
  V3 right, up, toward;
  double scale = 1, ox = 0, oy = 0;
  std::array<double, 2> screen(V3 p) const { return {ox + scale * dot(p, right), oy - scale * dot(p, up)}; }
  double depth(V3 p) const { return dot(p, toward); }
};

/// The ffmpeg arguments for the container of `path` (.mp4, .webm, .gif);
/// std::invalid_argument for another extension.
std::string codec_for(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".mp4") return "-f mp4 -c:v libx264 -pix_fmt yuv420p -crf 20 -movflags +faststart";
  if (ext == ".webm") return "-f webm -c:v libvpx-vp9 -b:v 0 -crf 34 -row-mt 1";
  if (ext == ".gif")
    return "-f gif -filter_complex \"split[a][b];[a]palettegen=stats_mode=diff[p];[b][p]paletteuse=dither=bayer\"";
  throw std::invalid_argument("video: '" + path + "': unknown format '" + ext + "' (use .mp4, .webm or .gif)");
}

/// The frames of a run: the figure seen by a camera that frames everything
/// it ever shows, drawn at any time of the track.
class Frames {
 public:
  Frames(const Figure& figure, const Track& track, const VideoOptions& options)
      : figure_(figure), track_(track), options_(options), nb_(figure.bodies.size()) {
    frame();
  }

  /// The colour behind everything.
  const Rgb& background() const { return background_; }

  /// Draws the frame at time t into img.
  void draw(double t, Image& img) const {
    const std::size_t k =
        static_cast<std::size_t>(std::upper_bound(track_.t.begin(), track_.t.end(), t) - track_.t.begin()) - 1;
    draw_fixed(img);
    draw_trails(k, img);
    draw_links(k, img);
    draw_bodies(k, t, img);
    draw_time_bar(t, img);
  }

 private:
  static constexpr double kBar = 14;  ///< height of the time bar (px)
  const Figure& figure_;
  const Track& track_;
  const VideoOptions& options_;
  std::size_t nb_;
  Camera cam_;
  V3 centre_;
  double span_ = 1, point_radius_ = 0, margin_ = 0;
  const Rgb background_ = detail::rgb(0xf4f4f0), ink_ = detail::rgb(0x333333);

  V3 body(std::size_t k, std::size_t b) const {
    const std::size_t i = (k * nb_ + b) * 3;
    return V3{track_.positions[i], track_.positions[i + 1], track_.positions[i + 2]};
  }
  Rgb colour(std::size_t b) const {
    return detail::rgb(figure_.bodies[b].color >= 0 ? figure_.bodies[b].color
                                                    : kPalette[b % (sizeof kPalette / sizeof kPalette[0])]);
  }
  double radius_px(std::size_t b) const {
    return cam_.scale * (figure_.bodies[b].radius > 0 ? figure_.bodies[b].radius : point_radius_);
  }

  /// The extent of everything shown, the plane of motion when there is one
  /// (seen face on), and the scale that fits the extent into the frame.
  void frame() {
    V3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    auto grow = [&](V3 p, double r) {
      for (int a = 0; a < 3; ++a) {
        at(lo, a) = std::min(at(lo, a), at(p, a) - r);
        at(hi, a) = std::max(at(hi, a), at(p, a) + r);
      }
    };
    V3 clo = lo, chi = hi;  // centres and fixed points only
    auto grow_centre = [&](V3 p) {
      for (int a = 0; a < 3; ++a) {
        at(clo, a) = std::min(at(clo, a), at(p, a));
        at(chi, a) = std::max(at(chi, a), at(p, a));
      }
    };
    for (std::size_t k = 0; k < track_.t.size(); ++k)
      for (std::size_t b = 0; b < nb_; ++b) {
        grow(body(k, b), figure_.bodies[b].radius);
        grow_centre(body(k, b));
      }
    for (const Point& p : figure_.pivots) grow(v3(p), 0), grow_centre(v3(p));
    for (const auto* list : {&figure_.rods, &figure_.springs})
      for (const auto& s : *list)
        if (s.b < 0) grow(v3(s.anchor), 0), grow_centre(v3(s.anchor));
    for (const auto& bx : figure_.boxes) grow(v3(bx.min), 0), grow(v3(bx.max), 0);
    for (const auto& s : figure_.spheres) grow(v3(s.centre), s.radius);
    for (const auto& c : figure_.circles) grow(v3(c.centre), c.radius);
    if (lo.x > hi.x) lo = {-1, -1, -1}, hi = {1, 1, 1};
    span_ = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-9});
    centre_ = 0.5 * (lo + hi);
    point_radius_ = 0.025 * span_;
    int flat = -1;
    for (int a = 0; a < 3 && nb_ > 0; ++a)
      if (at(chi, a) - at(clo, a) <= 1e-9 * span_) {
        flat = a;
        break;
      }
    const V3 up = unit(v3(figure_.up));
    if (flat >= 0) {
      V3 d{};
      at(d, flat) = 1;
      V3 u = up;
      if (std::abs(at(u, flat)) > 0.9) u = V3{}, at(u, (flat + 2) % 3) = 1;
      // from the side that shows the plane's other axes increasing rightwards
      cam_.right = unit(cross(u, d));
      if (cam_.right.x + cam_.right.y + cam_.right.z < 0) d = -1.0 * d, cam_.right = -1.0 * cam_.right;
      cam_.toward = d;
    } else {
      V3 side{1, 0, 0};
      if (std::abs(dot(up, side)) > 0.9) side = {0, 1, 0};
      const V3 across = unit(cross(up, side));
      cam_.toward = unit(0.45 * side - across + 0.45 * up);
      cam_.right = unit(cross(up, cam_.toward));
    }
    cam_.up = cross(cam_.toward, cam_.right);
    // Fit the projected extent (the 8 corners of the box around everything).
    double sx0 = 1e300, sx1 = -1e300, sy0 = 1e300, sy1 = -1e300;
    for (int c = 0; c < 8; ++c) {
      const V3 p{c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z};
      sx0 = std::min(sx0, dot(p, cam_.right));
      sx1 = std::max(sx1, dot(p, cam_.right));
      sy0 = std::min(sy0, dot(p, cam_.up));
      sy1 = std::max(sy1, dot(p, cam_.up));
    }
    margin_ = 0.06 * std::min(options_.width, options_.height);
    cam_.scale = std::min((options_.width - 2 * margin_) / std::max(sx1 - sx0, 1e-12 * span_),
                          (options_.height - 2 * margin_ - kBar) / std::max(sy1 - sy0, 1e-12 * span_));
    cam_.ox = options_.width / 2.0 - cam_.scale * 0.5 * (sx0 + sx1);
    cam_.oy = (options_.height - kBar) / 2.0 + cam_.scale * 0.5 * (sy0 + sy1);
  }

  /// Planes as patches, box edges, spheres, circles.
  void draw_fixed(Image& img) const {
    for (const auto& pl : figure_.planes) {
      const V3 nrm = unit(v3(pl.normal));
      const V3 p0 = centre_ - dot(centre_ - v3(pl.point), nrm) * nrm;
      V3 u = unit(cross(nrm, std::abs(nrm.x) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0}));
      const V3 v = cross(nrm, u);
      const double s = 0.6 * span_;
      std::vector<std::array<double, 2>> q;
      for (const auto& [a, c] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
        q.push_back(cam_.screen(p0 + (a * s) * u + (c * s) * v));
      img.polygon(q, detail::rgb(0xb9b4a6), 0.55);
      for (std::size_t i = 0; i < 4; ++i)
        img.line(q[i][0], q[i][1], q[(i + 1) % 4][0], q[(i + 1) % 4][1], 1.5, detail::rgb(0x6b665a));
    }
    for (const auto& bx : figure_.boxes) {
      auto corner = [&](int c) {
        return V3{c & 1 ? bx.max[0] : bx.min[0], c & 2 ? bx.max[1] : bx.min[1], c & 4 ? bx.max[2] : bx.min[2]};
      };
      for (int c = 0; c < 8; ++c)
        for (const int bit : {1, 2, 4})
          if (!(c & bit)) {
            const auto a = cam_.screen(corner(c)), e = cam_.screen(corner(c | bit));
            img.line(a[0], a[1], e[0], e[1], 1.2, detail::rgb(0x444444));
          }
    }
    for (const auto& s : figure_.spheres) {
      const auto c = cam_.screen(v3(s.centre));
      img.ring(c[0], c[1], cam_.scale * s.radius, 1.5, detail::rgb(0x7f96ab), 0.8);
    }
    for (const auto& c : figure_.circles) {
      const V3 nrm = unit(v3(c.normal));
      const V3 u = unit(cross(nrm, std::abs(nrm.x) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0})), v = cross(nrm, u);
      constexpr int kSides = 96;
      for (int i = 0; i < kSides; ++i) {
        const double a0 = 2 * M_PI * i / kSides, a1 = 2 * M_PI * (i + 1) / kSides;
        const auto p = cam_.screen(v3(c.centre) + (c.radius * std::cos(a0)) * u + (c.radius * std::sin(a0)) * v);
        const auto q = cam_.screen(v3(c.centre) + (c.radius * std::cos(a1)) * u + (c.radius * std::sin(a1)) * v);
        img.line(p[0], p[1], q[0], q[1], 1.5, detail::rgb(0x666666));
      }
    }
  }

  /// Trails up to sample k (up to 12 bodies, when there are at most 24).
  void draw_trails(std::size_t k, Image& img) const {
    if (nb_ > 24) return;
    for (std::size_t b = 0; b < std::min<std::size_t>(nb_, 12); ++b) {
      const Rgb c = colour(b);
      const Rgb light{0.65 * c.r + 0.35 * background_.r, 0.65 * c.g + 0.35 * background_.g,
                      0.65 * c.b + 0.35 * background_.b};
      const std::size_t step = std::max<std::size_t>(1, k / 2000);
      for (std::size_t j = step; j <= k; j += step) {
        const auto p = cam_.screen(body(j - step, b)), q = cam_.screen(body(j, b));
        img.line(p[0], p[1], q[0], q[1], 1.2, light);
      }
    }
  }

  /// Rods, springs and pivots at sample k.
  void draw_links(std::size_t k, Image& img) const {
    auto end = [&](const Figure::Segment& s) {
      return s.b >= 0 ? body(k, static_cast<std::size_t>(s.b)) : v3(s.anchor);
    };
    for (const auto& s : figure_.rods) {
      const auto a = cam_.screen(body(k, static_cast<std::size_t>(s.a))), e = cam_.screen(end(s));
      img.line(a[0], a[1], e[0], e[1], 2, ink_);
    }
    for (const auto& s : figure_.springs) {
      const V3 a = body(k, static_cast<std::size_t>(s.a)), e = end(s), axis = e - a;
      const V3 side = (0.6 * point_radius_) * unit(cross(cam_.toward, axis));
      constexpr int kCoils = 12;
      auto prev = cam_.screen(a);
      for (int j = 0; j <= 2 * kCoils + 1; ++j) {
        V3 p = j > 2 * kCoils ? e : a + (0.1 + 0.8 * j / (2.0 * kCoils)) * axis;
        if (j > 0 && j < 2 * kCoils) p = p + ((j % 2) ? 1.0 : -1.0) * side;
        const auto q = cam_.screen(p);
        img.line(prev[0], prev[1], q[0], q[1], 1.5, detail::rgb(0x7a5c00));
        prev = q;
      }
    }
    for (const Point& p : figure_.pivots) {
      const auto c = cam_.screen(v3(p));
      img.sphere(c[0], c[1], std::max(2.5, 0.4 * cam_.scale * point_radius_), detail::rgb(0x222222));
    }
  }

  /// Bodies at sample k, far to near; those in an event within the last
  /// quarter second of playback before t ringed.
  void draw_bodies(std::size_t k, double t, Image& img) const {
    const double flash = 0.25 * (track_.t.back() - track_.t.front()) / options_.seconds;
    std::vector<std::size_t> order(nb_);
    for (std::size_t b = 0; b < nb_; ++b) order[b] = b;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return cam_.depth(body(k, a)) < cam_.depth(body(k, b)); });
    std::vector<bool> flashing(nb_, false);
    for (const Event& e : track_.events)
      if (e.t <= t && e.t > t - flash) {
        if (e.bodies.empty()) flashing.assign(nb_, true);
        for (const int b : e.bodies)
          if (b >= 0 && static_cast<std::size_t>(b) < nb_) flashing[static_cast<std::size_t>(b)] = true;
      }
    for (const std::size_t b : order) {
      const auto c = cam_.screen(body(k, b));
      img.sphere(c[0], c[1], radius_px(b), colour(b));
      if (flashing[b] && nb_ <= 24) img.ring(c[0], c[1], radius_px(b) + 4, 2.5, detail::rgb(0xc83c28));
    }
  }

  /// The time bar at t, with the events' ticks.
  void draw_time_bar(double t, Image& img) const {
    const double t0 = track_.t.front(), t1 = track_.t.back();
    const double y = options_.height - kBar / 2 - 2, x0 = margin_, x1 = options_.width - margin_;
    img.line(x0, y, x1, y, 4, detail::rgb(0xd0d0c8));
    img.line(x0, y, x0 + (x1 - x0) * (t - t0) / std::max(t1 - t0, 1e-300), y, 4, detail::rgb(0x1f77b4));
    const std::size_t every = std::max<std::size_t>(1, track_.events.size() / 400);
    for (std::size_t j = 0; j < track_.events.size(); j += every) {
      const double x = x0 + (x1 - x0) * (track_.events[j].t - t0) / std::max(t1 - t0, 1e-300);
      img.line(x, y - 6, x, y - 3, 1, detail::rgb(0xc83c28));
    }
  }
};

}  // namespace

void write_video(const std::string& path, const Figure& figure, const Track& track, const VideoOptions& options) {
  const std::string codec = codec_for(path);
  if (options.width < 16 || options.height < 16 || options.width % 2 || options.height % 2)
    throw std::invalid_argument("video: width and height must be even and at least 16 px, got " +
                                std::to_string(options.width) + "x" + std::to_string(options.height));
  if (!(options.fps > 0) || !(options.seconds > 0))
    throw std::invalid_argument("video: fps and seconds must be positive");
  if (std::system("ffmpeg -version >/dev/null 2>&1") != 0)
    throw std::runtime_error("video: ffmpeg not found; install it with: apt-get install ffmpeg");
  detail::check(figure, track);  // the page's rules: sizes, finite values, indices in range
  // What a failed call must not leave: an older video that looks like this one.
  std::error_code stale;
  fs::remove(path, stale);
  const Frames frames(figure, track, options);
  const std::size_t count =
      std::max<std::size_t>(2, static_cast<std::size_t>(std::lround(options.fps * options.seconds)));
  const double t0 = track.t.front(), t1 = track.t.back();

  // The frames as PPM images through a pipe into ffmpeg, into a partial file
  // renamed when ffmpeg has succeeded.
  const std::string partial = path + ".partial", log = path + ".ffmpeg.log";
  const std::string command = "ffmpeg -hide_banner -loglevel error -y -f image2pipe -c:v ppm -framerate " +
                              std::to_string(options.fps) + " -i - " + codec + " " + quoted(partial) + " 2>" +
                              quoted(log);
  // A failing ffmpeg closes the pipe: the write then fails instead of raising SIGPIPE.
  struct IgnorePipe {
    void (*old)(int) = std::signal(SIGPIPE, SIG_IGN);
    ~IgnorePipe() { std::signal(SIGPIPE, old); }
  } ignore_pipe;
  std::FILE* pipe = popen(command.c_str(), "w");
  if (!pipe) throw std::runtime_error("video: cannot start ffmpeg");
  std::vector<std::uint8_t> ppm;
  bool write_ok = true;
  for (std::size_t f = 0; f < count && write_ok; ++f) {
    const double t = t0 + (t1 - t0) * static_cast<double>(f) / static_cast<double>(count - 1);
    Image img(options.width, options.height, frames.background());
    frames.draw(t, img);
    img.write_ppm(ppm);
    write_ok = std::fwrite(ppm.data(), 1, ppm.size(), pipe) == ppm.size();
  }
  const int status = pclose(pipe);
  std::error_code ec;
  if (!write_ok || status != 0) {
    std::ifstream in(log);
    std::ostringstream why;
    why << in.rdbuf();
    fs::remove(partial, ec);
    fs::remove(log, ec);
    throw std::runtime_error("video: ffmpeg failed writing '" + path + "'" +
                             (why.str().empty() ? std::string() : ": " + why.str()));
  }
  fs::remove(log, ec);
  fs::rename(partial, path, ec);
  if (ec) {
    fs::remove(partial, ec);
    throw std::runtime_error("video: cannot rename '" + partial + "' to '" + path + "'");
  }
}

}  // namespace lagrangian::view
