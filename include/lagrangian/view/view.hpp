#pragma once
/// \file view.hpp
/// The animation page of a run: `animation.html`, one self-contained file
/// (three.js and the page's script inlined, the samples embedded) that shows
/// the bodies moving in space, with the energy and the coordinates against
/// time beside them, and works offline from `file://`.
///
/// A page is written from a Figure (what is drawn: bodies as spheres, rods,
/// springs, pivots, fixed planes, the walls of a box, fixed spheres and
/// circles) and a Track (where the bodies are at each sample, in metres, and
/// the series plotted against time). `lagrangian run` writes one for every
/// scene (`--no-animation` or `output.animation = false` to skip); from C++,
/// scene::run_and_write() (scene/model_run.hpp) writes it for a model of
/// particles in one call, or fill a Figure and a Track from a run's samples
/// and call write_animation(). Target `lagrangian::view` (linked by
/// `lagrangian::scene`).
///
/// The page: play/pause (space bar), speed, a time slider, trails on/off, a
/// camera that orbits (drag), pans (right or shift drag) and zooms (wheel);
/// scenes whose bodies all move in one coordinate plane open looking along
/// that plane's normal. Events are ticks on the charts' time axis and flash
/// in the view when playback passes them. More than 400 bodies are drawn as
/// shaded point sprites.
///
/// Size: the samples are thinned evenly (every k-th, the last always kept)
/// so that the positions take at most Options::max_position_bytes; the page
/// states how many of how many samples it shows.

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace lagrangian::view {

/// A point or direction in space (m, or unitless for directions).
using Point = std::array<double, 3>;

/// What is drawn besides the bodies' motion.
struct Figure {
  /// A moving body, drawn as a sphere of its radius (m); radius 0 draws a
  /// point mass as a small sphere sized to the scene (2.5 % of its extent).
  struct Body {
    std::string name;
    double radius = 0;
    int color = -1;  ///< 0xRRGGBB; −1: the page's palette by index
  };
  /// A straight rod or a spring from body `a` to body `b`, or to the fixed
  /// point `anchor` (m) when b < 0.
  struct Segment {
    int a = 0;
    int b = -1;
    Point anchor{0, 0, 0};
  };
  /// A fixed plane through `point` with normal `normal`, drawn as a square
  /// patch under the motion.
  struct Plane {
    std::string name;
    Point point{0, 0, 0};
    Point normal{0, 0, 1};
  };
  /// The walls of an axis-aligned box (m).
  struct Box {
    Point min{0, 0, 0};
    Point max{1, 1, 1};
  };
  /// A fixed sphere (a surface a body moves on), drawn translucent.
  struct Sphere {
    Point centre{0, 0, 0};
    double radius = 1;
  };
  /// A fixed circle (a hoop or a track), drawn as a line.
  struct Circle {
    Point centre{0, 0, 0};
    Point normal{0, 0, 1};
    double radius = 1;
  };

  std::vector<Body> bodies;
  std::vector<Segment> rods;
  std::vector<Segment> springs;
  std::vector<Point> pivots;  ///< fixed points drawn as small dark spheres
  std::vector<Plane> planes;
  std::vector<Box> boxes;
  std::vector<Sphere> spheres;
  std::vector<Circle> circles;
  Point up{0, 0, 1};  ///< the direction shown upwards (against gravity)
};

/// A quantity against time, one value per sample of the Track.
struct Series {
  std::string name;
  std::string unit;
  std::vector<double> values;
};

/// An event on the time axis, flashed in the view.
struct Event {
  double t = 0;               ///< s
  std::string kind;           ///< "impact", "rest", …
  std::string label;          ///< e.g. the bodies or the contact, "ball-floor"
  std::vector<int> bodies;    ///< indices into Figure::bodies to flash; empty: all
};

/// Where the bodies are over time, and what is plotted beside them.
struct Track {
  std::vector<double> t;          ///< sample times (s), non-decreasing
  /// Body centres: t.size() × Figure::bodies.size() × 3 values (m), sample
  /// by sample, body by body, x y z.
  std::vector<double> positions;
  Series energy;                  ///< plotted when it has values (one per sample)
  /// The run's energy scale (J; RunReport::energy_scale): the energy chart is
  /// relative to it where E0 = 0. 0: relative to the largest |E| instead.
  double energy_scale = 0;
  std::vector<Series> coordinates;  ///< plotted against time, one chart per unit
  std::vector<Event> events;
  /// Samples of the run these were thinned from (stated on the page); 0:
  /// t.size().
  std::size_t samples_total = 0;
  /// Said under the charts, e.g. which coordinates are left out.
  std::string coordinates_note;
};

/// How the page is written.
struct Options {
  std::string title = "lagrangian";
  std::string description;
  /// The positions embedded take at most this many bytes (4 per value,
  /// base64: ×4/3); samples are thinned evenly to fit.
  std::size_t max_position_bytes = 12u << 20;
  std::size_t max_frames = 20000;      ///< and at most this many samples
  std::size_t max_coordinates = 12;    ///< coordinates plotted (the first that move)
};

/// What write_animation() wrote.
struct Written {
  std::string path;
  std::size_t samples_total = 0;   ///< samples of the run
  std::size_t samples_shown = 0;   ///< samples in the page
  std::size_t bytes = 0;           ///< size of the file
};

/// The stride k such that every k-th of `samples` samples of `bodies` bodies
/// (and the last) fit the options' budget: the rule write_animation() thins
/// by, for readers that thin while reading. The first and the last sample
/// are always kept, even when one sample alone is over the budget.
std::size_t sample_stride(std::size_t samples, std::size_t bodies, const Options& options);

/// True when this build has the page (three.js bundled at build time; see
/// docs/animation.md). Without it, write_animation() throws.
bool page_available();

/// Writes the page to `path` (through `path.partial`, renamed when
/// complete; nothing is left on failure). Throws std::invalid_argument
/// naming the field and the value when the track does not match the figure
/// (sizes, non-finite or decreasing times, non-finite positions, a series of
/// the wrong length, an event body out of range) and std::runtime_error when
/// the file cannot be written.
Written write_animation(const std::string& path, const Figure& figure, const Track& track,
                        const Options& options = {});

/// How write_video() draws.
struct VideoOptions {
  int width = 960;       ///< px, even
  int height = 540;      ///< px, even
  double fps = 30;       ///< frames per second of the video
  double seconds = 10;   ///< length of the video: the whole run, at a constant speed
};

/// Writes the run as a video for slides and documents: the figure drawn in
/// software — an orthographic view from the page's opening direction (the
/// plane of motion for planar scenes), bodies as shaded discs far to near,
/// rods, springs, pivots, planes, box edges, spheres, circles, trails for up
/// to 12 bodies, bodies in an event ringed for a quarter second, a time bar
/// with the events' ticks — encoded by ffmpeg (Debian's `ffmpeg`) as
/// H.264 MP4 (`.mp4`), VP9 WebM (`.webm`) or an animated GIF (`.gif`, with a
/// palette made for the video). Each video frame shows the last sample at or
/// before its time. Writes through `path.partial`; throws
/// std::invalid_argument for an unknown extension or bad sizes and
/// std::runtime_error when ffmpeg is missing or fails (its message
/// included), leaving nothing.
void write_video(const std::string& path, const Figure& figure, const Track& track, const VideoOptions& options = {});

}  // namespace lagrangian::view
