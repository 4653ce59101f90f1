// The animation page writer (view.hpp): what it refuses, how it thins, what a
// scene run writes. What the page draws is checked in a real browser
// (tests/browser/check_page.mjs).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/run.hpp"
#include "lagrangian/view/view.hpp"

namespace fs = std::filesystem;
using namespace lagrangian;

namespace {

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("lagrangian_test_view_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// A ball thrown at 45°: x = v t, z = v t − ½ g t², sampled every 1 ms.
struct Throw {
  view::Figure figure;
  view::Track track;
  explicit Throw(std::size_t samples) {
    figure.bodies.push_back({"ball", 0.1, -1});
    const double v = 5, g = 9.81;
    for (std::size_t k = 0; k < samples; ++k) {
      const double t = 1e-3 * static_cast<double>(k);
      track.t.push_back(t);
      track.positions.insert(track.positions.end(), {v * t, 0.0, v * t - 0.5 * g * t * t});
      track.energy.values.push_back(1.0);
    }
    track.energy.name = "energy";
    track.energy.unit = "J";
  }
};

std::string invalid(const view::Figure& f, const view::Track& t, const fs::path& path) {
  try {
    view::write_animation(path.string(), f, t);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(View, ThePageIsBuiltIn) { EXPECT_TRUE(view::page_available()); }

TEST(View, StrideKeepsTheBudgetAndTheLastSample) {
  view::Options o;
  o.max_frames = 1000;
  o.max_position_bytes = std::numeric_limits<std::size_t>::max();
  for (const std::size_t n : {2u, 999u, 1000u, 1001u, 1999u, 2000u, 2001u, 123457u}) {
    const std::size_t k = view::sample_stride(n, 3, o);
    // every k-th sample from 0 and the last one
    const std::size_t kept = (n - 1) / k + 1 + ((n - 1) % k != 0 ? 1 : 0);
    EXPECT_LE(kept, o.max_frames) << "n = " << n;
    if (k > 1) {
      const std::size_t finer = (n - 1) / (k - 1) + 1 + ((n - 1) % (k - 1) != 0 ? 1 : 0);
      EXPECT_GT(finer, o.max_frames) << "n = " << n << ": a smaller stride would have fitted";
    }
  }
  // 1000 bodies in 1 MB: 12 kB a sample, 87 samples fit
  o.max_position_bytes = 1u << 20;
  const std::size_t k = view::sample_stride(10001, 1000, o);
  EXPECT_LE((10000 + k - 1) / k + 1, (1u << 20) / 12000u);
}

TEST(View, WritesThinnedSamplesAndSaysSo) {
  const fs::path dir = fresh_dir("thinned");
  Throw th(10001);
  view::Options o;
  o.title = "a </script> title & more";
  o.max_frames = 500;
  const view::Written w = view::write_animation((dir / "animation.html").string(), th.figure, th.track, o);
  EXPECT_EQ(w.samples_total, 10001u);
  EXPECT_LE(w.samples_shown, 500u);
  EXPECT_GE(w.samples_shown, 400u);
  const std::string page = read(dir / "animation.html");
  EXPECT_EQ(page.size(), w.bytes);
  EXPECT_NE(page.find(std::to_string(w.samples_shown) + " of 10001 samples shown"), std::string::npos);
  // the last sample is kept: t = 10 s
  EXPECT_NE(page.find(",10],\"positions\""), std::string::npos);
  // the title cannot end the data's script element early
  EXPECT_NE(page.find("a &lt;/script&gt; title &amp; more"), std::string::npos);
  EXPECT_NE(page.find("a \\u003c/script\\u003e title \\u0026 more"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "animation.html.partial"));
  // nothing is fetched: no script or style from elsewhere
  EXPECT_EQ(page.find("<script src"), std::string::npos);
  EXPECT_EQ(page.find("<link"), std::string::npos);
}

TEST(View, BadTracksAreRefusedNamingTheFieldAndValue) {
  const fs::path dir = fresh_dir("bad");
  const fs::path path = dir / "animation.html";
  {
    Throw th(10);
    th.track.positions.pop_back();
    EXPECT_NE(invalid(th.figure, th.track, path)
                  .find("track.positions: has 29 values, expected samples (10) x bodies (1) x 3"),
              std::string::npos);
  }
  {
    Throw th(10);
    th.track.positions[3 * 4 + 2] = std::nan("");
    EXPECT_NE(invalid(th.figure, th.track, path).find("body 'ball' at t = 0.004 s is not finite"), std::string::npos);
  }
  {
    Throw th(10);
    th.track.t[5] = 0.001;
    EXPECT_NE(invalid(th.figure, th.track, path).find("track.t[5]: decreases"), std::string::npos);
  }
  {
    Throw th(10);
    th.track.events.push_back({0.002, "impact", "ball-floor", {1}});
    EXPECT_NE(invalid(th.figure, th.track, path).find("track.events[0].bodies: no body 1"), std::string::npos);
  }
  {
    Throw th(10);
    th.figure.rods.push_back({0, 3, {0, 0, 0}});
    EXPECT_NE(invalid(th.figure, th.track, path).find("figure.rods[0].b: no body 3"), std::string::npos);
  }
  {
    Throw th(10);
    th.track.energy.values.pop_back();
    EXPECT_NE(invalid(th.figure, th.track, path).find("track.energy: 'energy' has 9 values for 10 samples"),
              std::string::npos);
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(dir / "animation.html.partial"));
}

TEST(View, AnUnwritablePathLeavesNothing) {
  Throw th(10);
  const fs::path path = fs::temp_directory_path() / "lagrangian_test_view_missing_dir" / "sub" / "animation.html";
  fs::remove_all(path.parent_path().parent_path());
  EXPECT_THROW(view::write_animation(path.string(), th.figure, th.track), std::runtime_error);
  EXPECT_FALSE(fs::exists(path.parent_path()));
}

TEST(View, SceneRunsWriteThePageUnlessTold) {
  scene::Scene s;
  s.name = "drop";
  s.bodies.push_back({"ball", 1.0, 0.05, {0, 0, 1}, {0, 0, 0}});
  s.gravity = scene::UniformGravity{};
  s.run.t_end = 0.3;
  s.output.plots = false;
  s.output.directory = fresh_dir("scene").string();
  const scene::RunResult r = scene::run(s);
  const fs::path page = fs::path(s.output.directory) / "animation.html";
  EXPECT_TRUE(fs::exists(page));
  EXPECT_EQ(r.animation_note, "");
  EXPECT_NE(std::find(r.files.begin(), r.files.end(), page.string()), r.files.end());
  // The samples are those of trajectory.csv: 0.3 s every 0.01 s.
  EXPECT_NE(read(page).find("31 of 31 samples shown"), std::string::npos);

  s.output.animation = false;
  scene::run(s);
  EXPECT_FALSE(fs::exists(page)) << "a run without the page removes the old one";
}

namespace {

/// The frames of a video decoded by ffmpeg, as RGB bytes.
std::vector<std::vector<unsigned char>> frames_of(const fs::path& video, int w, int h) {
  const std::string cmd = "ffmpeg -loglevel error -i '" + video.string() + "' -f rawvideo -pix_fmt rgb24 -";
  std::FILE* p = popen(cmd.c_str(), "r");
  std::vector<std::vector<unsigned char>> out;
  if (!p) return out;
  std::vector<unsigned char> f(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  while (std::fread(f.data(), 1, f.size(), p) == f.size()) out.push_back(f);
  pclose(p);
  return out;
}

}  // namespace

// The video of a throw, read back pixel by pixel: the ball's drawn centre
// moves uniformly across and on a parabola up and down, and the ratio of the
// parabola's t² coefficient to the sideways speed is g / (2 v) whatever the
// scale of the picture.
TEST(View, TheVideoShowsTheThrowsParabola) {
  const fs::path dir = fresh_dir("video");
  Throw th(1001);  // 1 s
  th.figure.bodies[0].color = 0xff0000;
  th.figure.bodies[0].radius = 0.1;
  view::VideoOptions o;
  o.width = 320;
  o.height = 240;
  o.fps = 25;
  o.seconds = 2;
  view::write_video((dir / "throw.mp4").string(), th.figure, th.track, o);
  ASSERT_TRUE(fs::exists(dir / "throw.mp4"));
  EXPECT_FALSE(fs::exists(dir / "throw.mp4.partial"));
  const auto frames = frames_of(dir / "throw.mp4", o.width, o.height);
  ASSERT_EQ(frames.size(), 50u);
  // Centroid of the red pixels of each frame against the frame's time.
  std::vector<double> t, cx, cy;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    double sx = 0, sy = 0, count = 0;
    for (int y = 0; y < o.height - 20; ++y)  // above the time bar
      for (int x = 0; x < o.width; ++x) {
        const unsigned char* p = &frames[f][(static_cast<std::size_t>(y) * o.width + x) * 3];
        if (p[0] > 120 && p[1] < 70 && p[2] < 70) sx += x, sy += y, ++count;
      }
    ASSERT_GT(count, 10) << "frame " << f << " shows no ball";
    // the sample shown: the last at or before the frame's time
    t.push_back(std::floor(1000.0 * static_cast<double>(f) / 49.0 + 1e-9) / 1000.0);
    cx.push_back(sx / count);
    cy.push_back(sy / count);
  }
  // Least squares: cx = a0 + a1 t; cy = b0 + b1 t + b2 t².
  auto fit = [&](const std::vector<double>& v, int order, double& residual) {
    const int m = order + 1;
    std::vector<double> ata(static_cast<std::size_t>(m * m), 0), atb(static_cast<std::size_t>(m), 0);
    for (std::size_t k = 0; k < t.size(); ++k)
      for (int i = 0; i < m; ++i) {
        atb[static_cast<std::size_t>(i)] += std::pow(t[k], i) * v[k];
        for (int j = 0; j < m; ++j) ata[static_cast<std::size_t>(i * m + j)] += std::pow(t[k], i + j);
      }
    for (int i = 0; i < m; ++i)  // Gauss-Jordan
      for (int r = 0; r < m; ++r)
        if (r != i) {
          const double f = ata[static_cast<std::size_t>(r * m + i)] / ata[static_cast<std::size_t>(i * m + i)];
          for (int c = 0; c < m; ++c)
            ata[static_cast<std::size_t>(r * m + c)] -= f * ata[static_cast<std::size_t>(i * m + c)];
          atb[static_cast<std::size_t>(r)] -= f * atb[static_cast<std::size_t>(i)];
        }
    std::vector<double> c(static_cast<std::size_t>(m));
    for (int i = 0; i < m; ++i)
      c[static_cast<std::size_t>(i)] = atb[static_cast<std::size_t>(i)] / ata[static_cast<std::size_t>(i * m + i)];
    residual = 0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      double model = 0;
      for (int i = 0; i < m; ++i) model += c[static_cast<std::size_t>(i)] * std::pow(t[k], i);
      residual = std::max(residual, std::abs(model - v[k]));
    }
    return c;
  };
  double rx = 0, ry = 0;
  const auto a = fit(cx, 1, rx);
  const auto b = fit(cy, 2, ry);
  EXPECT_LT(rx, 1.0) << "sideways motion is not uniform on screen";
  EXPECT_LT(ry, 1.0) << "vertical motion is not a parabola on screen";
  EXPECT_GT(a[1], 0) << "x increases rightwards";
  EXPECT_GT(b[2], 0) << "the parabola opens downwards on screen (y down)";
  // screen: cx = ox + s v t, cy = oy - s (v t - g t²/2)  =>  b2 / a1 = g / (2 v)
  EXPECT_NEAR(b[2] / a[1], 9.81 / (2 * 5.0), 0.01 * 9.81 / 10.0);
  EXPECT_NEAR(-b[1] / a[1], 1.0, 0.01) << "v_z / v_x = 1 at 45 degrees";
}

TEST(View, AVideoOfAnUnknownFormatIsRefused) {
  Throw th(10);
  const fs::path path = fresh_dir("video_bad") / "throw.avi";
  EXPECT_THROW(view::write_video(path.string(), th.figure, th.track), std::invalid_argument);
  EXPECT_FALSE(fs::exists(path));
}

// An impact between bodies whose names have dashes of their own flashes
// those two bodies (the contact is "left-ball-right-ball"), not every body.
TEST(View, EventsFlashTheirBodiesWhateverTheirNames) {
  scene::Scene s;
  s.name = "dashes";
  s.bodies.push_back({"left-ball", 1.0, 0.1, {0, 0, 0}, {1, 0, 0}});
  s.bodies.push_back({"right-ball", 1.0, 0.1, {1, 0, 0}, {0, 0, 0}});
  s.bodies.push_back({"far", 1.0, 0.1, {0, 5, 0}, {0, 0, 0}});
  s.sphere_contacts = scene::SphereContacts{};
  s.run.t_end = 1.5;
  s.run.engine = "ode";
  s.output.plots = false;
  s.output.directory = fresh_dir("dashes").string();
  const scene::RunResult r = scene::run(s);
  ASSERT_EQ(r.report.impacts, 1u);
  ASSERT_EQ(r.report.events.front().name, "left-ball-right-ball");
  const std::string page = read(fs::path(s.output.directory) / "animation.html");
  EXPECT_NE(page.find("\"label\":\"left-ball-right-ball\",\"bodies\":[0,1]"), std::string::npos);
}
