// PNG previews of space-colonisation veins (Cairo behind this header): stroked veins over the leaf outline.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "venation/colonisation.h"

namespace cellform::exporters {

/// Drawing options for write_vein_png().
struct PngParams {
  int size = 1024;                       ///< pixels: the longer side of the image (16 to 20000)
  double margin = 10;                    ///< pixels of background around the drawing
  double min_stroke = 1.0;               ///< pixels: thinnest drawn vein (radius 0 or before compute_widths)
  std::uint32_t background = 0xffffff;   ///< 0xRRGGBB outside the leaf (opaque)
  std::uint32_t blade = 0xd8ecc0;        ///< 0xRRGGBB fill of the leaf outline
  std::uint32_t margin_line = 0x4a7a2a;  ///< 0xRRGGBB of the outline, stroked 1 pixel wide
  std::uint32_t vein = 0x2b3a1a;         ///< 0xRRGGBB of the veins
};

/// Where write_vein_png() puts a model point: pixel = ((x - lo_x) * scale + margin, (hi_y - y) * scale +
/// margin), y pointing up as in veins.svg. The drawing (outline, and vein nodes with their radii) is
/// fitted so that its longer side spans size - 2 margin pixels.
struct PngFrame {
  int width = 0, height = 0;  ///< pixels
  double scale = 1;           ///< pixels per model unit
  double lo_x = 0, hi_y = 0;  ///< model units
  double margin = 0;          ///< pixels
  double px(double x) const { return (x - lo_x) * scale + margin; }
  double py(double y) const { return (hi_y - y) * scale + margin; }
};

/// The frame write_vein_png() uses for this tree and outline. Throws core::InvalidInput for a size
/// outside 16..20000 or a margin that leaves no room.
PngFrame png_frame(const venation::VeinTree& tree, const venation::Outline& outline, const PngParams& params = {});

/// Draws the outline (filled, stroked) and every vein segment as an antialiased line of width 2 * radius
/// of its child node (an anastomosis: of the finer of the two nodes it joins; at least min_stroke) with round caps, in
/// the PngFrame above, and writes an opaque RGB PNG atomically (temporary name, then rename). core::FileError on
/// failure.
void write_vein_png(const std::filesystem::path& path, const venation::VeinTree& tree, const venation::Outline& outline,
                    const PngParams& params = {});

/// A decoded image: pixels row by row from the top, 0xAARRGGBB (premultiplied alpha; opaque images have AA = ff).
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint32_t> pixels;
  std::uint32_t at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

/// Reads a PNG file (any PNG Cairo decodes). core::FileError if it is missing or not a PNG.
Image read_png(const std::filesystem::path& path);

}  // namespace cellform::exporters
