// Leaf blade outlines: parametric shapes, triangular-wave teeth, outline files, simplicity checks.
#include "venation/leaf_shape.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <sstream>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace cellform::venation {

using core::InvalidInput;

namespace {

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

int orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double v = cross(b - a, c - a);
  return (v > 0) - (v < 0);
}

bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= p.y() &&
         p.y() <= std::max(a.y(), b.y());
}

bool segments_touch(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (o1 != o2 && o3 != o4) return true;
  return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) || (o3 == 0 && on_segment(c, d, a)) ||
         (o4 == 0 && on_segment(c, d, b));
}

/// The margin offset outward around a sharp concave corner crosses itself in a small loop (a swallowtail);
/// the outer margin runs straight through the crossing. Cuts every loop of at most `reach` edges out at
/// its crossing point. Larger crossings are left for validate_outline to report.
Outline without_local_loops(const Outline& o, std::size_t reach) {
  const std::size_t n = o.points.size();
  if (n < 8) return o;
  Outline out;
  out.points.push_back(o.points[0]);
  Vec2 a = o.points[0];  // the current edge runs from a (a vertex, or a crossing on edge i) to vertex i + 1
  std::size_t i = 0;
  while (i < n) {
    const Vec2 b = o.points[(i + 1) % n];
    bool cut = false;
    for (std::size_t d = reach; d >= 2 && !cut; --d) {  // the farthest crossing: nested loops go at once
      const std::size_t j = i + d;
      if (j + 1 >= n) continue;  // not across the start: the petiole stays
      const Vec2& c = o.points[j];
      const Vec2& e = o.points[j + 1];
      const double den = cross(b - a, e - c);
      if (den == 0 || !segments_touch(a, b, c, e)) continue;
      a = a + (cross(c - a, e - c) / den) * (b - a);  // the crossing; the margin goes on along edge j
      out.points.push_back(a);
      i = j;
      cut = true;
    }
    if (cut) continue;  // the rest of edge j may cross a later edge too
    if (i + 1 < n) out.points.push_back(b);
    a = b;
    ++i;
  }
  return out;
}

double tri(double x) { return 1.0 - std::abs(2.0 * (x - std::floor(x)) - 1.0); }

/// Adds triangular-wave teeth along the outward normal (outline counter-clockwise, starting at the petiole).
Outline add_teeth(const Outline& smooth, const std::vector<TriangularWave>& teeth, double fade_radius) {
  int max_count = 1;
  for (const auto& t : teeth) max_count = std::max(max_count, t.count);
  const std::size_t n0 = smooth.points.size();
  std::vector<double> cum(n0 + 1, 0.0);
  for (std::size_t i = 0; i < n0; ++i) cum[i + 1] = cum[i] + (smooth.points[(i + 1) % n0] - smooth.points[i]).norm();
  const double total = cum[n0];
  // In a concave bend of radius R an outward offset beyond R folds the margin over itself (the sinuses
  // between lobes): there the teeth are at most half the bend's radius, from the circle through each
  // smooth vertex and its neighbours (a real margin's teeth shrink into its sinuses, too).
  std::vector<double> room(n0, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < n0; ++i) {
    const Vec2& a = smooth.points[(i + n0 - 1) % n0];
    const Vec2& b = smooth.points[i];
    const Vec2& c = smooth.points[(i + 1) % n0];
    const double turn = cross(b - a, c - b);  // < 0: concave (the outline runs counter-clockwise)
    if (turn < 0) room[i] = 0.5 * (b - a).norm() * (c - b).norm() * (c - a).norm() / (2 * -turn);
  }
  // Samples: every smooth vertex (a sharp bend keeps its shape) and points evenly spaced along the
  // margin, at least 16 per tooth; each with its arc length and its room
  struct Sample {
    Vec2 p;
    double s, room;
  };
  // (a sample closer than a third of the even spacing to the one before is dropped, or replaced by a
  // smooth vertex: near-coincident samples would turn the normals between them)
  const std::size_t even = std::max<std::size_t>(n0, static_cast<std::size_t>(16 * max_count));
  const double close = total / static_cast<double>(even) / 3;
  std::vector<Sample> dense;
  auto add = [&](const Sample& q, bool vertex) {
    if (!dense.empty() && q.s - dense.back().s < close) {
      if (vertex && dense.size() > 1) dense.back() = {q.p, q.s, std::min(q.room, dense.back().room)};
      return;
    }
    dense.push_back(q);
  };
  std::size_t seg = 0;
  for (std::size_t k = 0; k < even; ++k) {
    const double s = total * static_cast<double>(k) / static_cast<double>(even);
    for (; cum[seg + 1] < s; ++seg)  // the smooth vertices passed on the way
      add({smooth.points[(seg + 1) % n0], cum[seg + 1], room[(seg + 1) % n0]}, true);
    const Vec2& a = smooth.points[seg];
    const Vec2& b = smooth.points[(seg + 1) % n0];
    const double len = cum[seg + 1] - cum[seg];
    add({len > 0 ? Vec2(a + (b - a) * ((s - cum[seg]) / len)) : a, s, std::min(room[seg], room[(seg + 1) % n0])},
        false);
  }
  for (++seg; seg < n0; ++seg)
    if (total - cum[seg] >= close) add({smooth.points[seg], cum[seg], room[seg]}, true);
  const std::size_t n = dense.size();
  // Teeth fade out within fade_radius of the petiole: in the notch of a cordate or palmate base the
  // normals converge, and full-height teeth there would cross each other (real leaves are entire at the
  // base, too).
  const Vec2 petiole = smooth.points[0];
  Outline out;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2& p = dense[k].p;
    const Vec2 e = dense[(k + 1) % n].p - dense[(k + n - 1) % n].p;
    const Vec2 normal = Vec2(e.y(), -e.x()).normalized();
    const double u = dense[k].s / total;
    double offset = 0;
    for (const auto& t : teeth) offset += t.amplitude * tri(t.count * u);
    // fourth power: a cardioid's notch narrows like d^1.5 with the distance d from the petiole, the
    // palmate one like d^3, and the teeth must shrink faster than that
    const double f = fade_radius > 0 ? std::min(1.0, (p - petiole).norm() / fade_radius) : 1.0;
    const double fade = (f * f) * (f * f);
    double cap = dense[k].room;
    // a narrow sinus: the facing flank, straight ahead along the normal, is as near as the bend is sharp
    for (std::size_t j = 0; j < n0; ++j) {
      const Vec2& a = smooth.points[j];
      const Vec2 e2 = smooth.points[(j + 1) % n0] - a;
      const double den = cross(normal, e2);
      if (den == 0) continue;
      const Vec2 w = a - p;
      const double t = cross(w, e2) / den, v = cross(w, normal) / den;  // p + t normal = a + v e2
      if (t > 1e-9 * total && v >= 0 && v <= 1) cap = std::min(cap, 0.45 * t);
    }
    out.points.push_back(p + std::min(fade * offset, cap) * normal);
  }
  // a loop round a corner spans about its teeth's depth each way: that many samples, with room to spare
  double depth = 0;
  for (const auto& t : teeth) depth += t.amplitude;
  const double reach = 64 + std::ceil(4 * depth / (total / static_cast<double>(even)));
  return without_local_loops(out, static_cast<std::size_t>(std::min(reach, static_cast<double>(n) / 4)));
}

}  // namespace

double signed_area(const Outline& o) {
  // about the first vertex: about the origin, an outline far from it summed huge products that cancel (a thin
  // one at 1e7 got the wrong sign, and so the wrong winding, in about two of five trials)
  double a = 0;
  const std::size_t n = o.points.size();
  for (std::size_t i = 1; i + 1 < n; ++i) a += cross(o.points[i] - o.points[0], o.points[i + 1] - o.points[0]);
  return 0.5 * a;
}

void validate_outline(const Outline& o, const std::string& what, const OutlineLines* from) {
  const std::size_t n = o.points.size();
  // vertex i (from 0) and edge i (from vertex i to the next) as a user finds them
  auto vertex_name = [&](std::size_t i) {
    return from ? "the vertex of line " + std::to_string(from->line[i]) : "vertex " + std::to_string(i);
  };
  auto edges_name = [&](std::size_t i, std::size_t j) {
    return from ? "the edges from lines " + std::to_string(from->line[std::min(i, j)]) + " and " +
                      std::to_string(from->line[std::max(i, j)])
                : "edges " + std::to_string(std::min(i, j) + 1) + " and " + std::to_string(std::max(i, j) + 1);
  };
  auto coordinate = [&](double x) { return core::number_text(from ? std::ldexp(x, from->exponent) : x); };
  if (n < 3) throw InvalidInput(what + ": an outline needs at least 3 vertices, got " + std::to_string(n));
  for (std::size_t i = 0; i < n; ++i)
    if (!o.points[i].allFinite()) throw InvalidInput(what + ": " + vertex_name(i) + " is not finite");
  // sweep over edges sorted by their lower x: only edges overlapping in x are compared
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  auto lo_x = [&](std::size_t i) { return std::min(o.points[i].x(), o.points[(i + 1) % n].x()); };
  auto hi_x = [&](std::size_t i) { return std::max(o.points[i].x(), o.points[(i + 1) % n].x()); };
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return lo_x(a) < lo_x(b) || (lo_x(a) == lo_x(b) && a < b); });
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t i = order[a];
    for (std::size_t b = a + 1; b < n && lo_x(order[b]) <= hi_x(i); ++b) {
      const std::size_t j = order[b];
      const bool adjacent = (i + 1) % n == j || (j + 1) % n == i;
      const Vec2 &p = o.points[i], &q = o.points[(i + 1) % n], &r = o.points[j], &s = o.points[(j + 1) % n];
      if (adjacent) {
        // adjacent edges share one vertex; they intersect elsewhere only by folding back along one line
        const bool i_first = (i + 1) % n == j;
        const Vec2& shared = i_first ? q : p;
        const Vec2& before = i_first ? p : r;
        const Vec2& after = i_first ? s : q;
        if (n > 3 && orient(before, shared, after) == 0 && (after - shared).dot(before - shared) > 0)
          throw InvalidInput(what + ": the outline folds back on itself at " + vertex_name(i_first ? j : i));
        continue;
      }
      if (segments_touch(p, q, r, s)) {
        // where: the crossing point, or for edges along one line, an end of one lying on the other
        const double den = cross(q - p, s - r);
        const Vec2 at = den != 0                                      ? Vec2(p + (cross(r - p, s - r) / den) * (q - p))
                        : orient(p, q, r) == 0 && on_segment(p, q, r) ? r
                        : orient(p, q, s) == 0 && on_segment(p, q, s) ? s
                                                                      : p;
        throw InvalidInput(what + ": the outline crosses itself at (" + coordinate(at.x()) + ", " + coordinate(at.y()) +
                           ") (" + edges_name(i, j) + ")");
      }
    }
  }
  // the area about the first vertex against the outline's own size: an outline far from the origin is no
  // flatter than the same outline at it (review: one at 1e6 was refused)
  Vec2 lo = o.points[0], hi = lo;
  for (const Vec2& q : o.points) {
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const double extent = (hi - lo).maxCoeff();
  if (!(std::abs(signed_area(o)) > 1e-12 * extent * extent))
    throw InvalidInput(what + ": the outline encloses no area (all vertices on a line?)");
}

double distance_to_boundary(const Outline& o, const Vec2& p) {
  double best = std::numeric_limits<double>::infinity();
  const std::size_t n = o.points.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = o.points[i];
    const Vec2 e = o.points[(i + 1) % n] - a;
    const double l2 = e.squaredNorm();
    const double t = l2 > 0 ? std::clamp((p - a).dot(e) / l2, 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * e - p).norm());
  }
  return best;
}

Outline make_outline(const ShapeParams& sp) {
  if (!(sp.length > 0 && std::isfinite(sp.length)))
    throw InvalidInput("shape.length must be a positive number of model units");
  if (!(sp.width > 0 && std::isfinite(sp.width)))
    throw InvalidInput("shape.width must be a positive number of model units");
  if (sp.samples < 16) throw InvalidInput("shape.samples must be at least 16");
  if (!(sp.lobe_depth >= 0 && sp.lobe_depth < 1)) throw InvalidInput("shape.lobe_depth must be in [0, 1)");
  if (sp.kind == ShapeKind::lobed && sp.lobes < 1)
    throw InvalidInput("shape.lobes must be at least 1 for a lobed leaf");
  if (sp.kind == ShapeKind::palmate && sp.lobes < 2)
    throw InvalidInput("shape.lobes must be at least 2 for a palmate leaf");
  for (const auto& t : sp.teeth)
    if (!(t.amplitude >= 0 && std::isfinite(t.amplitude)) || t.count < 1)
      throw InvalidInput("shape.teeth: each wave needs amplitude >= 0 (model units) and count >= 1");
  const int n = sp.samples;
  const double L = sp.length, W = sp.width;
  Outline o;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * M_PI * k / n;  // starts at the petiole, counter-clockwise
    Vec2 p;
    switch (sp.kind) {
      case ShapeKind::ellipse:
        p = Vec2(std::sin(t), 0.5 * L * (1 - std::cos(t)));
        break;
      case ShapeKind::ovate:
        p = Vec2(std::sin(t) * (1 + 0.35 * std::cos(t)), 0.5 * L * (1 - std::cos(t)));
        break;
      case ShapeKind::cordate: {  // cardioid about the petiole, angle from the +y axis
        const double th = t - M_PI;
        const double r = L * 0.5 * (1 + std::cos(th));
        p = Vec2(-r * std::sin(th), r * std::cos(th));
        break;
      }
      case ShapeKind::lobed: {  // ellipse about its centre with an even number of waves: flat at petiole and tip
        const double psi = t, phi = t - M_PI / 2;
        const double a = 0.5 * W, b = 0.5 * L;
        const double r = 1.0 / std::sqrt(std::pow(std::cos(phi) / a, 2) + std::pow(std::sin(phi) / b, 2));
        const double f = 1 - sp.lobe_depth * 0.5 * (1 - std::cos((2.0 * sp.lobes + 2) * psi));
        p = Vec2(r * f * std::cos(phi) / (0.5 * W), 0.5 * L + r * f * std::sin(phi));
        break;
      }
      case ShapeKind::palmate: {  // lobes every 1.6 pi / (lobes - 1) radians about the petiole
        const double th = t - M_PI;
        const double spacing = 1.6 * M_PI / (sp.lobes - 1);
        const double f = 1 - sp.lobe_depth * 0.5 * (1 - std::cos(2 * M_PI * th / spacing));
        const double r = L * std::sqrt(std::max(0.0, std::cos(th / 2))) * f;
        p = Vec2(-r * std::sin(th), r * std::cos(th));
        break;
      }
    }
    o.points.push_back(p);
  }
  if (sp.kind == ShapeKind::palmate || sp.kind == ShapeKind::cordate) {
    // petiole vertex coincides with neighbours' limit r -> 0: keep it once
    o.points.front() = Vec2::Zero();
  }
  // scale x to the requested width
  double wmin = 0, wmax = 0;
  for (const auto& p : o.points) {
    wmin = std::min(wmin, p.x());
    wmax = std::max(wmax, p.x());
  }
  for (auto& p : o.points) p.x() *= W / (wmax - wmin);
  if (!sp.teeth.empty()) {
    // the fade starts at four total amplitudes (at most a tenth of the length) and widens (up to half the
    // length) while a narrow notch
    // still makes the teeth cross; teeth too deep for the blade itself are still refused
    double amplitude = 0;
    for (const auto& t : sp.teeth) amplitude += t.amplitude;
    const Outline smooth = o;
    for (double fade = std::min(4 * amplitude, 0.1 * L);; fade *= 1.5) {
      o = add_teeth(smooth, sp.teeth, fade);
      try {
        validate_outline(o, "shape.teeth");
        break;
      } catch (const InvalidInput& e) {
        if (fade * 1.5 > 0.5 * L) {
          std::string m = e.what();
          const auto at = m.find("crosses itself ");
          m = at == std::string::npos ? m.substr(m.find(':') + 2) : "the margin " + m.substr(at);
          throw InvalidInput("shape.teeth: teeth " + core::number_text(amplitude) +
                             " deep cross each other on this outline (" + m + "); use shallower or fewer teeth");
        }
      }
    }
  } else {
    validate_outline(o, "shape");
  }
  return o;
}

Outline parse_outline(const std::string& text, const std::string& source) {
  Outline o;
  // a UTF-8 byte-order mark, which some editors write, is no content
  std::istringstream in(text.rfind("\xEF\xBB\xBF", 0) == 0 ? text.substr(3) : text);
  std::string line;
  int line_no = 0, last_line = 0;
  OutlineLines lines;  // each vertex's line, for the messages of validate_outline
  while (std::getline(in, line)) {
    ++line_no;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    // "x y", or "x,y" as spreadsheets export it
    const bool commas = line.find(',') != std::string::npos;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ls(line);
    std::vector<std::string> words;
    for (std::string w; ls >> w;) words.push_back(w);
    if (words.empty()) continue;  // blank or comment line
    const std::string at = source + ":" + std::to_string(line_no) + ": ";
    auto shown = [](const std::string& word) {  // a binary file's bytes are not echoed
      const bool printable =
          std::all_of(word.begin(), word.end(), [](unsigned char ch) { return ch >= 32 && ch < 127; });
      return !printable         ? std::string("bytes that are not text (is it an outline file?)")
             : word.size() > 40 ? "'" + word.substr(0, 40) + "...'"
                                : "'" + word + "'";
    };
    double xy[2] = {0, 0};
    for (std::size_t k = 0; k < std::min<std::size_t>(words.size(), 2); ++k) {
      const std::string& w = words[k];
      const char* end = w.data() + w.size();
      const bool plus = w[0] == '+' && w.size() > 1 && w[1] != '+' && w[1] != '-';  // from_chars takes no '+'
      auto [ptr, ec] = std::from_chars(w.data() + (plus ? 1 : 0), end, xy[k]);
      if (ec == std::errc::result_out_of_range && ptr == end) {
        // too small is zero, as a stream reads it; too large is no number
        xy[k] = std::strtod(w.c_str(), nullptr);
        if (std::isinf(xy[k]))
          throw InvalidInput(at + (k ? "y" : "x") + " " + shown(w) +
                             " is beyond the range of numbers (about 1.8e308): scale the outline down");
        ec = std::errc();
      }
      if (ec != std::errc() || ptr != end)
        throw InvalidInput(
            at + "expected two numbers \"x y\", got " + shown(w) + (k == 0 ? std::string() : " as y") +
            (w.find_first_of(";:") != std::string::npos ? " (numbers go apart by spaces or one comma)" : ""));
      if (!std::isfinite(xy[k]))
        throw InvalidInput(at + "coordinates must be finite numbers, got " + shown(w) + " as " + (k ? "y" : "x"));
    }
    if (words.size() == 1) throw InvalidInput(at + "expected two numbers \"x y\", got one (" + shown(words[0]) + ")");
    if (words.size() > 2)
      throw InvalidInput(at + "expected two numbers \"x y\", got " + std::to_string(words.size()) + " (" +
                         shown(words[2]) + " is a third)" +
                         (commas ? "; decimals take a point, not a comma (\"0.5 1.25\" or \"0.5,1.25\")" : ""));
    const double x = xy[0], y = xy[1];
    o.points.emplace_back(x, y);
    lines.line.push_back(static_cast<std::size_t>(line_no));
    last_line = line_no;
  }
  if (o.points.size() < 4)
    throw InvalidInput(source + ": an outline needs at least 3 vertices plus the first repeated at the end, got " +
                       std::to_string(o.points.size()) + " lines of coordinates");
  // closed when the last vertex repeats the first, up to the rounding of an export (a millionth of the size)
  double size = 0;
  for (const Vec2& p : o.points) size = std::max(size, (p - o.points.front()).cwiseAbs().maxCoeff());
  // a second contour after the first closed (a hole, an island): one outline only (the first vertex repeated
  // again at the end, an export that closes a polyline twice, is no contour)
  const auto at_first = [&](std::size_t k) {
    return (o.points[k] - o.points.front()).cwiseAbs().maxCoeff() <= 1e-6 * size;
  };
  for (std::size_t k = 3; k + 1 < o.points.size(); ++k)
    if (at_first(k) && !at_first(k + 1))
      throw InvalidInput(source + ":" + std::to_string(lines.line[k + 1]) + ": the outline closed at line " +
                         std::to_string(lines.line[k]) + " (its vertex repeats the first), and " +
                         std::to_string(o.points.size() - k - 1) +
                         " more lines of coordinates follow: a leaf outline is one closed contour, without holes "
                         "or a second contour");
  if (!at_first(o.points.size() - 1))
    throw InvalidInput(source + ":" + std::to_string(last_line) +
                       ": the outline is open: its last vertex must repeat the first one to close it (they are " +
                       core::number_text((o.points.back() - o.points.front()).norm()) + " apart)");
  o.points.back() = o.points.front();
  o.points.pop_back();
  lines.line.pop_back();
  // a vertex repeated on the next line (an export that closes a polyline twice) is one vertex
  std::vector<Vec2> kept;
  std::vector<std::size_t> kept_lines;
  for (std::size_t i = 0; i < o.points.size(); ++i)
    if (kept.empty() || o.points[i] != kept.back()) {
      kept.push_back(o.points[i]);
      kept_lines.push_back(lines.line[i]);
    }
  while (kept.size() > 1 && kept.back() == kept.front()) {
    kept.pop_back();
    kept_lines.pop_back();
  }
  o.points = std::move(kept);
  lines.line = std::move(kept_lines);
  // any unit: coordinates near the ends of the double range are brought near 1 by a power of two (exact),
  // so that areas and crossings (products of two coordinates) neither overflow nor underflow
  double extent = 0;
  for (const Vec2& p : o.points) extent = std::max(extent, p.cwiseAbs().maxCoeff());
  if (extent > 0 && (extent > 1e100 || extent < 1e-100)) {
    int e = 0;
    std::frexp(extent, &e);
    for (Vec2& p : o.points) p = Vec2(std::ldexp(p.x(), -e), std::ldexp(p.y(), -e));
    lines.exponent = e;
  }
  validate_outline(o, source, &lines);
  if (signed_area(o) < 0) std::reverse(o.points.begin(), o.points.end());
  return o;
}

Outline read_outline(const std::filesystem::path& path) { return parse_outline(core::read_file(path), path.string()); }

OutlineIndex::OutlineIndex(const Outline& outline, bool grid) : outline_(outline) {
  const auto& p = outline_.points;
  const std::size_t n = p.size();
  lo_ = hi_ = p.front();
  for (const auto& q : p) {
    lo_ = lo_.cwiseMin(q);
    hi_ = hi_.cwiseMax(q);
  }
  area_ = std::abs(signed_area(outline_));
  const std::size_t bands = std::max<std::size_t>(1, static_cast<std::size_t>(std::sqrt(static_cast<double>(n))) * 2);
  band_height_ = std::max((hi_.y() - lo_.y()) / static_cast<double>(bands), 1e-300);
  std::vector<std::vector<std::size_t>> lists(bands);
  for (std::size_t i = 0; i < n; ++i) {
    const double y0 = std::min(p[i].y(), p[(i + 1) % n].y()), y1 = std::max(p[i].y(), p[(i + 1) % n].y());
    const auto b0 =
        static_cast<std::size_t>(std::clamp((y0 - lo_.y()) / band_height_, 0.0, static_cast<double>(bands - 1)));
    const auto b1 =
        static_cast<std::size_t>(std::clamp((y1 - lo_.y()) / band_height_, 0.0, static_cast<double>(bands - 1)));
    for (std::size_t b = b0; b <= b1; ++b) lists[b].push_back(i);
  }
  band_start_.assign(1, 0);
  for (const auto& l : lists) {
    band_edges_.insert(band_edges_.end(), l.begin(), l.end());
    band_start_.push_back(band_edges_.size());
  }
  // The grid: about 64 cells per vertex (at most 2^20), of the box's proportions.
  const double w = hi_.x() - lo_.x(), h = hi_.y() - lo_.y();
  const double reach = std::max({std::abs(lo_.x()), std::abs(lo_.y()), std::abs(hi_.x()), std::abs(hi_.y())});
  const double total = std::clamp(64.0 * static_cast<double>(n), 4096.0, 1048576.0);
  // cells far wider than the rounding of the coordinates, and coordinates whose products neither overflow nor
  // underflow (else the crossing test alone)
  const bool tame = reach > 1e-140 && reach < 1e140 && std::min(w, h) > 1e-140;
  if (!grid || !tame || !(std::min(w, h) / total > 1e-9 * reach)) return;
  const auto most = static_cast<long>(total);
  gx_ = std::clamp(std::lround(std::sqrt(total * w / h)), 1L, most);
  gy_ = std::clamp(std::lround(total / static_cast<double>(gx_)), 1L, most);
  const double cw = w / static_cast<double>(gx_), ch = h / static_cast<double>(gy_);
  inv_w_ = static_cast<double>(gx_) / w;
  inv_h_ = static_cast<double>(gy_) / h;
  cell_class_.assign(static_cast<std::size_t>(gx_ * gy_), 0);
  auto col = [&](double x) { return static_cast<long>(std::floor((x - lo_.x()) * inv_w_)); };
  auto row = [&](double y) { return static_cast<long>(std::floor((y - lo_.y()) * inv_h_)); };
  // Cells near an edge: for each row within a cell of the edge's y range, the edge's x extent over that
  // row widened by a cell up and down, then by a cell left and right. So a cell left unmarked is at least
  // about a cell from every edge, far beyond any rounding of the crossing test or of a point's cell.
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = p[i];
    const Vec2& c = p[(i + 1) % n];
    const double y_lo = std::min(a.y(), c.y()), y_hi = std::max(a.y(), c.y());
    const long r0 = std::max(0L, row(y_lo) - 1), r1 = std::min(gy_ - 1, row(y_hi) + 1);
    for (long r = r0; r <= r1; ++r) {
      const double ya = std::max(y_lo, lo_.y() + static_cast<double>(r - 1) * ch);
      const double yb = std::min(y_hi, lo_.y() + static_cast<double>(r + 2) * ch);
      double x0 = std::min(a.x(), c.x()), x1 = std::max(a.x(), c.x());
      if (c.y() != a.y() && ya <= yb) {
        const double xa = a.x() + (ya - a.y()) * (c.x() - a.x()) / (c.y() - a.y());
        const double xb = a.x() + (yb - a.y()) * (c.x() - a.x()) / (c.y() - a.y());
        x0 = std::max(x0, std::min(xa, xb));
        x1 = std::min(x1, std::max(xa, xb));
      }
      const long c0 = std::max(0L, col(std::min(x0, x1)) - 1), c1 = std::min(gx_ - 1, col(std::max(x0, x1)) + 1);
      for (long k = c0; k <= c1; ++k) cell_class_[static_cast<std::size_t>(r * gx_ + k)] = 2;
    }
  }
  // Runs of unmarked cells along a row lie on one side of the outline (a crossing between two of them
  // would have marked the cells round it): one crossing test per run, at the centre of its first cell.
  for (long r = 0; r < gy_; ++r) {
    std::uint8_t* line = cell_class_.data() + r * gx_;
    for (long k = 0; k < gx_;) {
      if (line[k] == 2) {
        ++k;
        continue;
      }
      const Vec2 centre(lo_.x() + (static_cast<double>(k) + 0.5) * cw, lo_.y() + (static_cast<double>(r) + 0.5) * ch);
      const std::uint8_t in = crossing_test(centre) ? 1 : 0;
      for (; k < gx_ && line[k] != 2; ++k) line[k] = in;
    }
  }
}

bool OutlineIndex::contains(const Vec2& q) const {
  if (outline_.points.empty() || q.x() < lo_.x() || q.x() > hi_.x() || q.y() < lo_.y() || q.y() > hi_.y()) return false;
  if (!cell_class_.empty()) {
    const long k = std::min(gx_ - 1, static_cast<long>((q.x() - lo_.x()) * inv_w_));
    const long r = std::min(gy_ - 1, static_cast<long>((q.y() - lo_.y()) * inv_h_));
    const std::uint8_t c = cell_class_[static_cast<std::size_t>(r * gx_ + k)];
    if (c != 2) return c == 1;
  }
  return crossing_test(q);
}

bool OutlineIndex::crossing_test(const Vec2& q) const {
  if (outline_.points.empty() || q.x() < lo_.x() || q.x() > hi_.x() || q.y() < lo_.y() || q.y() > hi_.y()) return false;
  const auto& p = outline_.points;
  const std::size_t n = p.size();
  const std::size_t bands = band_start_.size() - 1;
  const auto b =
      static_cast<std::size_t>(std::clamp((q.y() - lo_.y()) / band_height_, 0.0, static_cast<double>(bands - 1)));
  bool inside = false;
  for (std::size_t k = band_start_[b]; k < band_start_[b + 1]; ++k) {
    const std::size_t i = band_edges_[k];
    const Vec2& a = p[i];
    const Vec2& c = p[(i + 1) % n];
    if ((a.y() > q.y()) != (c.y() > q.y())) {
      const double x = a.x() + (q.y() - a.y()) * (c.x() - a.x()) / (c.y() - a.y());
      if (q.x() < x) inside = !inside;
    }
  }
  return inside;
}

bool OutlineIndex::segment_inside(const Vec2& a, const Vec2& b) const {
  if (!contains(b)) return false;
  const Vec2 lo = a.cwiseMin(b), hi = a.cwiseMax(b);
  if (!cell_class_.empty() && lo.x() >= lo_.x() && lo.y() >= lo_.y()) {  // every cell the box meets wholly inside
    auto cell = [](double offset, double inv, long count) {
      return std::min(count - 1, static_cast<long>(offset * inv));
    };
    const long k0 = cell(lo.x() - lo_.x(), inv_w_, gx_), k1 = cell(hi.x() - lo_.x(), inv_w_, gx_);
    const long r0 = cell(lo.y() - lo_.y(), inv_h_, gy_), r1 = cell(hi.y() - lo_.y(), inv_h_, gy_);
    bool clear = true;
    for (long r = r0; r <= r1 && clear; ++r)
      for (long k = k0; k <= k1 && clear; ++k) clear = cell_class_[static_cast<std::size_t>(r * gx_ + k)] == 1;
    if (clear) return true;
  }
  // a proper crossing with an edge of a band the segment's height meets: each end strictly on either side,
  // but for a start on the outline (a seed at the petiole; a node that rounding put just outside, within the
  // tolerance validate(Leaf) gives a seed), which may cross it there
  const double tolerance = 1e-6 * (hi_ - lo_).norm();
  const auto& p = outline_.points;
  const std::size_t n = p.size(), bands = band_start_.size() - 1;
  auto band = [&](double y) {
    return static_cast<std::size_t>(std::clamp((y - lo_.y()) / band_height_, 0.0, static_cast<double>(bands - 1)));
  };
  auto side = [](const Vec2& u, const Vec2& v, const Vec2& w) {
    const double d = (v.x() - u.x()) * (w.y() - u.y()) - (v.y() - u.y()) * (w.x() - u.x());
    return (d > 0) - (d < 0);
  };
  for (std::size_t bi = band(lo.y()); bi <= band(hi.y()); ++bi)
    for (std::size_t k = band_start_[bi]; k < band_start_[bi + 1]; ++k) {
      const Vec2& c = p[band_edges_[k]];
      const Vec2& d = p[(band_edges_[k] + 1) % n];
      if (side(a, b, c) * side(a, b, d) >= 0 || side(c, d, a) * side(c, d, b) >= 0) continue;
      const Vec2 e = d - c;  // not zero: c and d lie strictly on either side of the segment
      if (std::abs(e.x() * (a.y() - c.y()) - e.y() * (a.x() - c.x())) > tolerance * e.norm()) return false;
    }
  return true;
}

}  // namespace cellform::venation
