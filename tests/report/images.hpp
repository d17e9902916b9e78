#pragma once

// Decoding what the figures write, with libraries other than the drawing
// code's own paths: PNG headers by hand and pixels through cairo's PNG
// reader, SVG through expat.

#include <cstdint>
#include <string>
#include <vector>

#include "report/style.hpp"

namespace stepstone::reporttest {

/// True when `bytes` starts with the 8-byte PNG signature.
bool png_signature(const std::string& bytes);
/// Width and height from the IHDR chunk (which must come first), read by hand.
std::pair<std::uint32_t, std::uint32_t> png_size(const std::string& bytes);

struct Rgb {
    int r = 0, g = 0, b = 0;
    bool operator==(const Rgb&) const = default;
};

/// A decoded PNG (opaque pixels).
struct Image {
    int width = 0, height = 0;
    std::vector<std::uint32_t> argb;  ///< row-major
    Rgb at(int x, int y) const;
    /// Number of distinct colours.
    std::size_t colours() const;
    /// Fraction of pixels that are not pure white.
    double inked() const;
};
Image decode_png(const std::string& bytes);
/// The 8-bit pixel a colour is drawn as (each channel rounded from [0, 1] to 0-255).
Rgb rgb(report::Colour c);

/// What parsing an SVG found.
struct SvgFacts {
    bool well_formed = false;
    std::string error;
    std::string root;  ///< name of the root element
    std::size_t elements = 0;
    std::size_t titles = 0;  ///< <title> elements
    std::vector<std::string> title_texts;
};
SvgFacts parse_svg(const std::string& text);

/// Checks a figure's bytes: a PNG of `width` x `height` with some ink and
/// several colours, or a well-formed SVG. Returns "" or what is wrong.
std::string check_png(const std::string& bytes, int width, int height);
std::string check_svg(const std::string& text);

}  // namespace stepstone::reporttest
