// Initial point sets.
#include "forms/shapes.h"

#include <cmath>
#include <numbers>

#include "core/errors.h"

namespace cellform::forms {

namespace {
void check_positive(double v, const char* what) {
  if (!(v > 0) || !std::isfinite(v))
    throw core::InvalidInput(std::string(what) + " must be a positive number (model units), got " + std::to_string(v));
}
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

std::vector<Vec3> hex_rectangle(const Vec3& centre, const Vec3& normal, double width, double height, double spacing) {
  check_positive(width, "width");
  check_positive(height, "height");
  check_positive(spacing, "spacing");
  Vec3 u, v;
  plane_basis(unit_normal(normal), u, v);
  const double row = spacing * std::sqrt(3.0) / 2.0;
  const long nx = static_cast<long>(std::floor(width / 2 / spacing)) + 1;
  const long ny = static_cast<long>(std::floor(height / 2 / row));
  if (static_cast<double>(2 * nx + 1) * static_cast<double>(2 * ny + 1) > 5e7)
    throw core::InvalidInput("shape would need about " + std::to_string((2 * nx + 1) * (2 * ny + 1)) +
                             " cells (more than 50 million); raise the spacing or shrink the shape");
  std::vector<Vec3> out;
  for (long j = -ny; j <= ny; ++j) {
    const double shift = (j % 2 != 0) ? spacing / 2 : 0.0;
    for (long i = -nx; i <= nx; ++i) {
      const double x = static_cast<double>(i) * spacing + shift;
      if (std::abs(x) > width / 2 + 1e-9) continue;
      out.push_back(centre + x * u + static_cast<double>(j) * row * v);
    }
  }
  return out;
}

std::vector<Vec3> hex_disc(const Vec3& centre, const Vec3& normal, double radius, double spacing) {
  check_positive(radius, "radius");
  check_positive(spacing, "spacing");
  std::vector<Vec3> out;
  for (const Vec3& p : hex_rectangle(centre, normal, 2 * radius + 2 * spacing, 2 * radius + 2 * spacing, spacing))
    if ((p - centre).norm() <= radius + 1e-9) out.push_back(p);
  return out;
}

std::vector<Vec3> sphere_points(const Vec3& centre, double radius, double spacing) {
  check_positive(radius, "radius");
  check_positive(spacing, "spacing");
  const double area = 4 * std::numbers::pi * radius * radius;
  const auto n = static_cast<long>(std::max(4.0, std::round(area / (spacing * spacing * std::sqrt(3.0) / 2))));
  if (n > 50'000'000) throw core::InvalidInput("sphere would need " + std::to_string(n) + " cells; raise the spacing");
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
  const double len = (to - from).norm();
  const auto n = static_cast<long>(std::ceil(len / spacing));
  if (n > 50'000'000) throw core::InvalidInput("line would need " + std::to_string(n) + " cells; raise the spacing");
  std::vector<Vec3> out;
  for (long i = 0; i <= n; ++i)
    out.push_back(n == 0 ? from : from + (to - from) * (static_cast<double>(i) / static_cast<double>(n)));
  return out;
}

}  // namespace cellform::forms
