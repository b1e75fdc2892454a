// PNG previews of space-colonisation veins, drawn with Cairo (the only file that includes it).
#include "export/vein_png.h"

#include <cairo.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <memory>
#include <ostream>
#include <string>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "venation/vein_io.h"

namespace cellform::exporters {

namespace {

using venation::Index;
using venation::kNoIndex;
using venation::Outline;
using venation::Vec2;
using venation::VeinTree;

struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextDeleter {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
};
using Surface = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;
using Context = std::unique_ptr<cairo_t, ContextDeleter>;

void set_rgb(cairo_t* c, std::uint32_t rgb) {
  cairo_set_source_rgb(c, ((rgb >> 16) & 0xff) / 255.0, ((rgb >> 8) & 0xff) / 255.0, (rgb & 0xff) / 255.0);
}

struct PngSink {
  std::ostream* out;
  int error = 0;  // errno of the write that failed, if the stream set it
};

cairo_status_t write_to_stream(void* closure, const unsigned char* data, unsigned int length) {
  auto* sink = static_cast<PngSink*>(closure);
  errno = 0;
  sink->out->write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(length));
  if (*sink->out) return CAIRO_STATUS_SUCCESS;
  sink->error = errno;
  return CAIRO_STATUS_WRITE_ERROR;
}

}  // namespace

PngFrame png_frame(const VeinTree& tree, const Outline& outline, const PngParams& params) {
  if (params.size < 16 || params.size > 20000)
    throw core::InvalidInput("png size must be 16 to 20000 pixels, got " + std::to_string(params.size));
  if (!(params.margin >= 0 && 2 * params.margin < params.size - 1))
    throw core::InvalidInput("png margin must be >= 0 pixels and leave room for the drawing");
  auto [lo, hi] = venation::drawing_bounds(tree, outline);
  if (tree.radius.size() == tree.size())  // a thick vein at the edge (a petiole's) is drawn whole
    for (Index i = 0; i < tree.size(); ++i) {
      const Vec2 q(tree.positions[i].x(), tree.positions[i].y()), r = Vec2::Constant(std::max(tree.radius[i], 0.0));
      lo = lo.cwiseMin(q - r);
      hi = hi.cwiseMax(q + r);
    }
  const double extent = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-12});
  PngFrame f;
  f.margin = params.margin;
  f.scale = (params.size - 2 * params.margin) / extent;
  f.lo_x = lo.x();
  f.hi_y = hi.y();
  f.width = std::clamp(static_cast<int>(std::lround((hi.x() - lo.x()) * f.scale + 2 * params.margin)), 1, params.size);
  f.height = std::clamp(static_cast<int>(std::lround((hi.y() - lo.y()) * f.scale + 2 * params.margin)), 1, params.size);
  return f;
}

void write_vein_png(const std::filesystem::path& path, const VeinTree& tree, const Outline& outline,
                    const PngParams& params) {
  const PngFrame f = png_frame(tree, outline, params);
  const Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, f.width, f.height));
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    throw core::FileError("cannot write '" + path.string() + "': " + std::to_string(f.width) + " x " +
                          std::to_string(f.height) +
                          " image: " + cairo_status_to_string(cairo_surface_status(surface.get())));
  const Context context(cairo_create(surface.get()));
  cairo_t* c = context.get();
  set_rgb(c, params.background);
  cairo_paint(c);
  if (!outline.points.empty()) {
    for (std::size_t i = 0; i < outline.points.size(); ++i) {
      const Vec2& q = outline.points[i];
      if (i == 0)
        cairo_move_to(c, f.px(q.x()), f.py(q.y()));
      else
        cairo_line_to(c, f.px(q.x()), f.py(q.y()));
    }
    cairo_close_path(c);
    set_rgb(c, params.blade);
    cairo_fill_preserve(c);
    set_rgb(c, params.margin_line);
    cairo_set_line_width(c, 1.0);
    cairo_stroke(c);
  }
  set_rgb(c, params.vein);
  cairo_set_line_cap(c, CAIRO_LINE_CAP_ROUND);
  const bool widths = tree.radius.size() == tree.size();
  auto segment = [&](Index a, Index b, double r) {
    // no wider than the image: a wider stroke draws nothing more, and Cairo would take minutes over it
    cairo_set_line_width(c, std::min(std::max(params.min_stroke, 2 * r * f.scale), 2.0 * (f.width + f.height)));
    cairo_move_to(c, f.px(tree.positions[a].x()), f.py(tree.positions[a].y()));
    cairo_line_to(c, f.px(tree.positions[b].x()), f.py(tree.positions[b].y()));
    cairo_stroke(c);
  };
  for (Index i = 0; i < tree.size(); ++i)
    if (tree.parent[i] != kNoIndex) segment(tree.parent[i], i, widths ? tree.radius[i] : 0.0);
  // a loop's closing segment: the width of the finer vein it joins (as veins.svg and the print)
  for (const auto& [a, b] : tree.anastomoses) segment(a, b, widths ? std::min(tree.radius[a], tree.radius[b]) : 0.0);
  cairo_surface_flush(surface.get());
  if (cairo_status(c) != CAIRO_STATUS_SUCCESS)
    throw core::FileError("cannot draw '" + path.string() + "': " + cairo_status_to_string(cairo_status(c)));
  core::write_file_atomically(path, [&](std::ostream& out) {
    PngSink sink{&out};
    const cairo_status_t st = cairo_surface_write_to_png_stream(surface.get(), write_to_stream, &sink);
    if (st == CAIRO_STATUS_WRITE_ERROR)  // cairo's text ("error while writing to output stream") hides the cause
      throw core::FileError("cannot write '" + path.string() + "': " +
                            (sink.error != 0 ? std::string(std::strerror(sink.error)) : "write failed (disk full?)"));
    if (st != CAIRO_STATUS_SUCCESS)
      throw core::FileError("cannot write '" + path.string() + "': " + cairo_status_to_string(st));
  });
}

Image read_png(const std::filesystem::path& path) {
  const Surface surface(cairo_image_surface_create_from_png(path.c_str()));
  const cairo_status_t st = cairo_surface_status(surface.get());
  if (st != CAIRO_STATUS_SUCCESS)
    throw core::FileError("cannot read PNG '" + path.string() + "': " + cairo_status_to_string(st));
  cairo_surface_flush(surface.get());
  Image img;
  img.width = cairo_image_surface_get_width(surface.get());
  img.height = cairo_image_surface_get_height(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  const unsigned char* data = cairo_image_surface_get_data(surface.get());
  const bool opaque = cairo_image_surface_get_format(surface.get()) == CAIRO_FORMAT_RGB24;
  img.pixels.resize(static_cast<std::size_t>(img.width) * img.height);
  for (int y = 0; y < img.height; ++y) {
    const auto* row = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    for (int x = 0; x < img.width; ++x)
      img.pixels[static_cast<std::size_t>(y) * img.width + x] = opaque ? (row[x] | 0xff000000u) : row[x];
  }
  return img;
}

}  // namespace cellform::exporters
