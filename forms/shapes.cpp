// Initial point sets.
#include "forms/shapes.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/errors.h"

namespace cellform::forms {

namespace {
void check_positive(double v, const char* what) {
  if (!(v > 0) || !std::isfinite(v))
    throw core::InvalidInput(std::string(what) + " must be a positive number (model units), got " +
                             core::number_text(v));
}

// A shape places at most this many cells (the limit division.max_cells has too).
constexpr double kMaxShapeCells = 5e7;

// Refuses a shape whose cell count, estimated in double precision (so a huge size or a tiny spacing
// gives a huge or infinite count, never an overflowing integer), is above the limit. `what` names the
// sizes the count comes from, e.g. "radius 10 at spacing 0.1".
void check_cell_count(double count, const std::string& what) {
  if (count <= kMaxShapeCells) return;
  const std::string need = std::isfinite(count) ? "about " + core::number_text(count) + " cells (more than 50 million)"
                                                : "more than 50 million cells";
  throw core::InvalidInput(what + " would need " + need + "; raise the spacing or shrink the shape");
}
std::string at_spacing(double spacing) { return " at spacing " + core::number_text(spacing); }

Vec3 unit_normal(const Vec3& n) {
  const double len = n.norm();
  if (!(len > 0) || !std::isfinite(len)) throw core::InvalidInput("shape normal must be a non-zero vector");
  return n / len;
}
}  // namespace

void plane_basis(const Vec3& normal, Vec3& u, Vec3& v) {
  const Vec3 helper = std::abs(normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  u = (helper - helper.dot(normal) * normal).normalized();
  v = normal.cross(u);
}

namespace {
// The hexagonal lattice points of the width x height rectangle (model units) about `centre` in the
// plane of `normal`, rows `spacing` sqrt(3) / 2 apart, that `keep` accepts. Sizes already checked.
template <class Keep>
std::vector<Vec3> hex_lattice(const Vec3& centre, const Vec3& normal, double width, double height, double spacing,
                              const Keep& keep) {
  Vec3 u, v;
  plane_basis(unit_normal(normal), u, v);
  const double row = spacing * std::sqrt(3.0) / 2.0;
  const auto nx = static_cast<long>(std::floor(width / 2 / spacing) + 1);
  const auto ny = static_cast<long>(std::floor(height / 2 / row));
  std::vector<Vec3> out;
  for (long j = -ny; j <= ny; ++j) {
    const double shift = (j % 2 != 0) ? spacing / 2 : 0.0;
    for (long i = -nx; i <= nx; ++i) {
      const double x = static_cast<double>(i) * spacing + shift;
      if (std::abs(x) > width / 2 + 1e-9) continue;
      const Vec3 p = centre + x * u + static_cast<double>(j) * row * v;
      if (keep(p)) out.push_back(p);
    }
  }
  return out;
}
}  // namespace

double hex_rectangle_cells(double width, double height, double spacing) {
  // as hex_lattice places them: rows j = -ny..ny; a row's points x = i spacing (+ spacing / 2 on odd rows)
  // with |x| <= width / 2
  const double row = spacing * std::sqrt(3.0) / 2.0;
  const double ny = std::floor(height / 2 / row), half = (width / 2 + 1e-9) / spacing;
  const double even_rows = 2 * std::floor(ny / 2) + 1, odd_rows = 2 * ny + 1 - even_rows;
  return even_rows * (2 * std::floor(half) + 1) + odd_rows * 2 * std::floor(half + 0.5);
}

double hex_disc_cells(double radius, double spacing) {
  // the disc's own count: its area over a lattice cell's (the lattice square around it is not built
  // when the disc is refused, and holds 4 / pi times as many points)
  const double ratio = radius / spacing;  // squared after dividing: a tiny spacing cannot underflow to 0 first
  return std::numbers::pi * ratio * ratio / (std::sqrt(3.0) / 2) + 1;
}

double sphere_cells(double radius, double spacing) {
  const double ratio = radius / spacing;  // squared after dividing: a tiny spacing cannot underflow to 0 first
  return std::max(4.0, std::round(4 * std::numbers::pi * ratio * ratio / (std::sqrt(3.0) / 2)));
}

double line_cells(const Vec3& from, const Vec3& to, double spacing) {
  return std::ceil((to - from).norm() / spacing) + 1;
}

std::vector<Vec3> hex_rectangle(const Vec3& centre, const Vec3& normal, double width, double height, double spacing) {
  check_positive(width, "width");
  check_positive(height, "height");
  check_positive(spacing, "spacing");
  unit_normal(normal);
  check_cell_count(hex_rectangle_cells(width, height, spacing), "width " + core::number_text(width) + " x height " +
                                                                    core::number_text(height) + at_spacing(spacing));
  return hex_lattice(centre, normal, width, height, spacing, [](const Vec3&) { return true; });
}

std::vector<Vec3> hex_disc(const Vec3& centre, const Vec3& normal, double radius, double spacing) {
  check_positive(radius, "radius");
  check_positive(spacing, "spacing");
  unit_normal(normal);
  check_cell_count(hex_disc_cells(radius, spacing), "radius " + core::number_text(radius) + at_spacing(spacing));
  const double side = 2 * radius + 2 * spacing;
  return hex_lattice(centre, normal, side, side, spacing,
                     [&](const Vec3& p) { return (p - centre).norm() <= radius + 1e-9; });
}

std::vector<Vec3> sphere_points(const Vec3& centre, double radius, double spacing) {
  check_positive(radius, "radius");
  check_positive(spacing, "spacing");
  const double count = sphere_cells(radius, spacing);
  check_cell_count(count, "radius " + core::number_text(radius) + at_spacing(spacing));
  const auto n = static_cast<long>(count);
  std::vector<Vec3> out;
  out.reserve(static_cast<std::size_t>(n));
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (long i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (static_cast<double>(i) + 0.5) / static_cast<double>(n);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden * static_cast<double>(i);
    out.push_back(centre + radius * Vec3(r * std::cos(phi), r * std::sin(phi), z));
  }
  return out;
}

std::vector<Vec3> line_points(const Vec3& from, const Vec3& to, double spacing) {
  check_positive(spacing, "spacing");
  if (!from.allFinite() || !to.allFinite()) throw core::InvalidInput("line from and to must be finite positions");
  const double count = line_cells(from, to, spacing);
  check_cell_count(count, "length " + core::number_text((to - from).stableNorm()) + at_spacing(spacing));
  const auto n = static_cast<long>(count) - 1;
  std::vector<Vec3> out;
  for (long i = 0; i <= n; ++i)
    out.push_back(n == 0 ? from : from + (to - from) * (static_cast<double>(i) / static_cast<double>(n)));
  return out;
}

}  // namespace cellform::forms
