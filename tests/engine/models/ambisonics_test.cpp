// SPDX-License-Identifier: GPL-3.0-or-later
// AmbiX encoding gains against the published closed forms, and the bus rotation against re-encoding.

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <random>

#include "engine/models/ambisonics.hpp"

namespace {

// The real spherical harmonics up to order 3 in ACN order with SN3D normalisation and no
// Condon-Shortley phase, in Cartesian form for a unit direction (x, y, z): the table of Zotter & Frank,
// "Ambisonics" (Springer 2019), section 4.8 (Table 4.1 with N3D turned into SN3D by 1/sqrt(2n+1)), the
// same as Nachbar et al., "AmbiX - a suggested Ambisonics format" (2011), Table 1. Written out here
// independently of the engine's Legendre recurrences.
std::array<double, 16> table_sn3d(double x, double y, double z) {
    const double s3 = std::sqrt(3.0), s15 = std::sqrt(15.0), s58 = std::sqrt(5.0 / 8.0), s38 = std::sqrt(3.0 / 8.0);
    return {1.0,
            y,
            z,
            x,
            s3 * x * y,
            s3 * y * z,
            0.5 * (3.0 * z * z - 1.0),
            s3 * x * z,
            0.5 * s3 * (x * x - y * y),
            s58 * y * (3.0 * x * x - y * y),
            s15 * x * y * z,
            s38 * y * (5.0 * z * z - 1.0),
            0.5 * z * (5.0 * z * z - 3.0),
            s38 * x * (5.0 * z * z - 1.0),
            0.5 * s15 * z * (x * x - y * y),
            s58 * x * (x * x - 3.0 * y * y)};
}

ameoto::Vec3 random_direction(std::mt19937_64& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    for (;;) {
        const ameoto::Vec3 v{n(rng), n(rng), n(rng)};
        const double r = ameoto::norm(v);
        if (r > 1e-6) return v / r;
    }
}

}  // namespace

TEST_CASE("ambisonics: the encoding gains are the AmbiX (ACN, SN3D) spherical harmonics, orders 0 to 3") {
    std::mt19937_64 rng(21);
    for (int i = 0; i < 50; ++i) {
        const ameoto::Vec3 v = random_direction(rng);
        const auto want = table_sn3d(v.x, v.y, v.z);
        const double az = std::atan2(v.y, v.x), el = std::asin(v.z);
        for (int order = 0; order <= 3; ++order) {
            const auto got = ameoto::ambix_gains(az, el, order);
            const auto from_vector = ameoto::ambix_gains(3.7 * v, order);   // any length
            for (int k = 0; k < 16; ++k) {
                CAPTURE(i);
                CAPTURE(order);
                CAPTURE(k);
                // 1e-9: the brief's tolerance; both sides are a few double operations (about 1e-15).
                const double expect = k < ameoto::ambix_channels(order) ? want[static_cast<std::size_t>(k)] : 0.0;
                CHECK(std::abs(got[static_cast<std::size_t>(k)] - expect) < 1e-9);
                CHECK(std::abs(from_vector[static_cast<std::size_t>(k)] - expect) < 1e-9);
            }
        }
    }
    // The axes by name: W 1, front is X, left is Y, up is Z.
    const auto left = ameoto::ambix_gains(M_PI / 2, 0.0, 1), up = ameoto::ambix_gains(0.0, M_PI / 2, 1);
    CHECK(left[1] == doctest::Approx(1.0));
    CHECK(std::abs(left[3]) < 1e-15);
    CHECK(up[2] == doctest::Approx(1.0));
    CHECK_THROWS(ameoto::ambix_gains(0.0, 0.0, 4));
}

TEST_CASE("ambisonics: channel counts, orders and names") {
    CHECK(ameoto::ambix_channels(1) == 4);
    CHECK(ameoto::ambix_channels(3) == 16);
    CHECK(ameoto::ambix_order(9) == 2);
    CHECK(ameoto::ambix_order(5) == -1);
    CHECK(ameoto::ambix_channel_name(0) == "ACN 0 W");
    CHECK(ameoto::ambix_channel_name(3) == "ACN 3 X");
    CHECK(ameoto::ambix_channel_name(15) == "ACN 15 P");
}

TEST_CASE("ambisonics: the bus rotation equals encoding from the turned head's directions") {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI);
    for (int trial = 0; trial < 6; ++trial) {
        const double yaw = angle(rng), pitch = 0.5 * angle(rng), roll = angle(rng);
        const auto h = ameoto::head_rotation(yaw, pitch, roll);
        for (int order = 1; order <= 3; ++order) {
            const ameoto::AmbixRotation r = ameoto::AmbixRotation::from_orientation(yaw, pitch, roll, order);
            for (int i = 0; i < 20; ++i) {
                const ameoto::Vec3 v = random_direction(rng);
                const ameoto::Vec3 heard{h[0] * v.x + h[3] * v.y + h[6] * v.z, h[1] * v.x + h[4] * v.y + h[7] * v.z,
                                         h[2] * v.x + h[5] * v.y + h[8] * v.z};
                const auto in = ameoto::ambix_gains(v, order), want = ameoto::ambix_gains(heard, order);
                std::array<double, 16> out{};
                r.apply(in.data(), out.data());
                // 1e-9: the relation is exact; the fit's residual is rounding (about 1e-14 here).
                for (int k = 0; k < ameoto::ambix_channels(order); ++k)
                    CHECK(std::abs(out[static_cast<std::size_t>(k)] - want[static_cast<std::size_t>(k)]) < 1e-9);
            }
        }
    }
    // The conventions by name: a head turned 90 degrees left hears the left in front; raised 90 degrees
    // (nose up) it hears the zenith in front; rolled 90 degrees (right ear down) it hears the zenith on
    // its left.
    const auto turned = [](double yaw, double pitch, double roll, ameoto::Vec3 source) {
        const auto r = ameoto::AmbixRotation::from_orientation(yaw, pitch, roll, 1);
        const auto in = ameoto::ambix_gains(source, 1);
        std::array<double, 16> out{};
        r.apply(in.data(), out.data());
        return ameoto::Vec3{out[3], out[1], out[2]};   // X, Y, Z
    };
    const ameoto::Vec3 a = turned(M_PI / 2, 0, 0, {0, 1, 0}), b = turned(0, M_PI / 2, 0, {0, 0, 1}), c = turned(0, 0, M_PI / 2, {0, 0, 1});
    CHECK(a.x == doctest::Approx(1.0));
    CHECK(b.x == doctest::Approx(1.0));
    CHECK(c.y == doctest::Approx(1.0));
    CHECK(ameoto::AmbixRotation::identity(2).is_identity());
}
