#pragma once

#include <cstdint>

namespace stepstone::report {

/// An opaque sRGB colour, channels in [0, 1].
struct Colour {
    double r = 0.0, g = 0.0, b = 0.0;
    /// From 0xRRGGBB.
    static constexpr Colour hex(std::uint32_t rgb) {
        return {static_cast<double>((rgb >> 16) & 0xff) / 255.0, static_cast<double>((rgb >> 8) & 0xff) / 255.0,
                static_cast<double>(rgb & 0xff) / 255.0};
    }
};

// Okabe and Ito's palette, distinguishable with every common colour-vision
// deficiency. Series take them in this order.
inline constexpr Colour kBlue = Colour::hex(0x0072B2);
inline constexpr Colour kVermillion = Colour::hex(0xD55E00);
inline constexpr Colour kGreen = Colour::hex(0x009E73);
inline constexpr Colour kOrange = Colour::hex(0xE69F00);
inline constexpr Colour kSkyBlue = Colour::hex(0x56B4E9);
inline constexpr Colour kPurple = Colour::hex(0xCC79A7);
inline constexpr Colour kYellow = Colour::hex(0xF0E442);
inline constexpr Colour kBlack = Colour::hex(0x000000);
inline constexpr Colour kGrey = Colour::hex(0x7F7F7F);
inline constexpr Colour kWhite = Colour::hex(0xFFFFFF);
/// Labels, titles and legends.
inline constexpr Colour kText = Colour::hex(0x222222);

/// Series colour `index` (cycles through the palette).
Colour series_colour(int index);

/// The saliency ramp of the trajectory figures (the paper's Fig. 4 and 8):
/// white for 0 (or no match) to dark blue (0x08306B) for `t` = 1, linear in
/// sRGB; `t` is clamped to [0, 1].
Colour saliency_colour(double t);
inline constexpr Colour kSaliencyHigh = Colour::hex(0x08306B);

// The arena's colours.
inline constexpr Colour kFloor = Colour::hex(0xF2F2F2);
inline constexpr Colour kWall = Colour::hex(0x3C3C3C);
inline constexpr Colour kDoor = Colour::hex(0xA6611A);
inline constexpr Colour kBall = kOrange;
inline constexpr Colour kSwitch = kGreen;
inline constexpr Colour kBasket = kPurple;
/// Heading marks: white when the robot carries nothing, red when it carries a ball.
inline constexpr Colour kHeadingFree = kWhite;
inline constexpr Colour kHeadingCarrying = Colour::hex(0xD7191C);

/// Font family of every figure (fonts-dejavu-core, installed by setup-deps).
inline constexpr const char* kFont = "DejaVu Sans";

}  // namespace stepstone::report
