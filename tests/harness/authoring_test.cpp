// Scene authoring matrices (harness/authoring.hpp) against the textbook formulas they stand for
// (gluPerspective, gluLookAt, a rotation's action on the axes), and a matrix through the scene
// file and the front end.
#include "harness/authoring.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "harness/front_end.hpp"
#include "harness/reduce.hpp"

namespace {

using harness::Matrix4;

// m * (x, y, z, w), in double: the expected values below are exact to float precision.
std::array<double, 4> apply(const Matrix4& m, std::array<double, 4> p) {
    std::array<double, 4> out{};
    for (std::size_t r = 0; r < 4; ++r)
        for (std::size_t c = 0; c < 4; ++c) out[r] += double{m[4 * c + r]} * p[c];
    return out;
}

void expect_near4(const std::array<double, 4>& got, const std::array<double, 4>& want) {
    for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(got[i], want[i], 1e-5) << "component " << i;
}

TEST(Authoring, PerspectiveIsGluPerspective) {
    const double aspect = 1.5, n = 0.5, f = 20.0;
    const Matrix4 m = harness::perspective_matrix(60.0f, 1.5f, 0.5f, 20.0f);
    const double cot = 1.0 / std::tan(60.0 * std::numbers::pi / 360.0);
    // Column-major: (row r, column c) at [4c + r].
    EXPECT_NEAR(double{m[0]}, cot / aspect, 1e-6);
    EXPECT_NEAR(double{m[5]}, cot, 1e-6);
    EXPECT_NEAR(double{m[10]}, (f + n) / (n - f), 1e-6);
    EXPECT_EQ(m[11], -1.0f);
    EXPECT_NEAR(double{m[14]}, 2.0 * f * n / (n - f), 1e-6);
    EXPECT_EQ(m[15], 0.0f);
    // The near plane goes to NDC z = -1, the far plane to +1.
    const auto near_point = apply(m, {0, 0, -n, 1});
    const auto far_point = apply(m, {0, 0, -f, 1});
    EXPECT_NEAR(near_point[2] / near_point[3], -1.0, 1e-6);
    EXPECT_NEAR(far_point[2] / far_point[3], 1.0, 1e-5);
}

TEST(Authoring, LookAtMovesTheEyeToTheOriginLookingDownMinusZ) {
    const Matrix4 m = harness::look_at_matrix({1, 2, 5}, {1, 2, 0}, {0, 1, 0});
    expect_near4(apply(m, {1, 2, 5, 1}), {0, 0, 0, 1});   // the eye
    expect_near4(apply(m, {1, 2, 0, 1}), {0, 0, -5, 1});  // the centre, ahead
    expect_near4(apply(m, {1, 3, 5, 1}), {0, 1, 0, 1});   // up stays up
}

TEST(Authoring, RotationsTurnCounterClockwiseAndCompose) {
    const Matrix4 rz = harness::rotation_matrix(90.0f, {0, 0, 2});  // any length of axis
    expect_near4(apply(rz, {1, 0, 0, 1}), {0, 1, 0, 1});
    const Matrix4 t = harness::translation_matrix({10, 0, 0});
    // multiply(a, b) applies b first: rotate, then translate.
    expect_near4(apply(harness::multiply(t, rz), {1, 0, 0, 1}), {10, 1, 0, 1});
    expect_near4(apply(harness::multiply(rz, t), {1, 0, 0, 1}), {0, 11, 0, 1});
    expect_near4(apply(harness::scale_matrix({2, 3, 4}), {1, 1, 1, 1}), {2, 3, 4, 1});
    // A turn and its inverse give the identity, to float rounding.
    const Matrix4 back = harness::multiply(rz, harness::rotation_matrix(-90.0f, {0, 0, 1}));
    const Matrix4 id = harness::identity_matrix();
    for (std::size_t i = 0; i < 16; ++i) EXPECT_NEAR(double{back[i]}, double{id[i]}, 1e-6) << i;
}

TEST(Authoring, BadArgumentsAreRefused) {
    EXPECT_THROW(harness::perspective_matrix(0.0f, 1.0f, 0.1f, 1.0f), std::invalid_argument);
    EXPECT_THROW(harness::perspective_matrix(60.0f, 1.0f, 1.0f, 1.0f), std::invalid_argument);
    EXPECT_THROW(harness::look_at_matrix({0, 0, 0}, {0, 0, 0}, {0, 1, 0}), std::invalid_argument);
    EXPECT_THROW(harness::look_at_matrix({0, 0, 1}, {0, 0, 0}, {0, 0, 1}), std::invalid_argument);
    EXPECT_THROW(harness::rotation_matrix(10.0f, {0, 0, 0}), std::invalid_argument);
}

TEST(Authoring, AMatrixTravelsThroughTheSceneFileAndTheFrontEnd) {
    harness::SceneFile f;
    f.target = {16, 16, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 1};
    harness::SceneDraw d;
    d.state.viewport = {0, 0, 16, 16};
    for (const auto& p : {std::array<float, 2>{0.2f, 0.1f}, {0.7f, -0.4f}, {-0.3f, 0.6f}}) {
        harness::SceneVertex v;
        v.position = {p[0], p[1], 0.0f, 1.0f};
        v.position_size = 2;
        d.vertices.push_back(v);
    }
    const Matrix4 m = harness::multiply(harness::perspective_matrix(50.0f, 1.0f, 0.1f, 10.0f),
                                        harness::look_at_matrix({0, 0, 3}, {0, 0, 0}, {0, 1, 0}));
    harness::set_clip_matrix(d, m);
    EXPECT_EQ(d.space, harness::VertexSpace::Clip);
    EXPECT_EQ(d.vertices[0].position_size, 4u);
    f.draws.push_back(d);
    const auto again = harness::load_scene_text(harness::scene_to_json(f), "authored.json");
    ASSERT_TRUE(again.file.draws[0].matrix.has_value());
    EXPECT_EQ(*again.file.draws[0].matrix, m);  // bit for bit
    // The front end applies it in the format's order; the result is the matrix's action up
    // to float rounding.
    const auto c = harness::to_clip_space(again.file.draws[0], again.file.draws[0].vertices[1]);
    const auto want = apply(m, {0.7, -0.4, 0, 1});
    for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(double{c[i]}, want[i], 1e-5);
}

}  // namespace
