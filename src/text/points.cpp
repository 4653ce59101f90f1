// The mass points of a text model: r(q, t) and its derivatives along a path.
#include "lagrangian/ad.hpp"
#include "lagrangian/text/evaluate.hpp"
#include "lagrangian/text/text_model.hpp"

namespace lagrangian::text {

int TextModel::mass_point_count() const {
  int count = 0;
  for (const Point& pt : p_->definition.points) count += pt.mass > 0 ? 1 : 0;
  return count;
}

void TextModel::mass_points(const double* q, const double* dq, const double* ddq, double t, double dt,
                            PointMotion* out) const {
  // q(s) = q + dq s + ½ ddq s², t(s) = t + dt s: the value, first and second
  // derivatives of each coordinate along s are a Jet's v, g and h.
  using J = ad::Jet<double, 1, 2>;
  thread_local Vec<J, Dynamic> qj;
  const int n = size();
  if (qj.size() < n) qj.resize(n);
  for (int k = 0; k < n; ++k) {
    qj[k] = J(q[k]);
    qj[k].g[0] = dq[k];
    qj[k].h[0] = ddq != nullptr ? ddq[k] : 0.0;
  }
  J tj(t);
  tj.g[0] = dt;
  std::vector<J>& slots = detail::slots<J>();
  const auto& points = p_->definition.points;
  int k = 0;
  for (std::size_t b = 0; b < points.size(); ++b) {
    if (!(points[b].mass > 0)) continue;
    PointMotion& pm = out[k++];
    pm.mass = points[b].mass;
    for (std::size_t a = 0; a < 3; ++a) {
      const J x = evaluate(p_->points[b][a], qj, qj, tj, slots);
      pm.r[a] = x.v;
      pm.v[a] = x.g[0];
      pm.a[a] = x.h[0];
    }
  }
}

}  // namespace lagrangian::text
