// authoring.hpp: helpers for writing scenes in code: camera and model matrices for a draw's
// "matrix" (scene format, space "clip"), computed with GLM.
//
// Which arithmetic is GLM's and which must not be (docs/library.md, "GLM"):
//  - GLM computes these matrices: their 16 floats are the scene's input, written into the file
//    and read back bit for bit, so how they were computed does not matter to any renderer;
//  - GLM never applies a matrix to a vertex: the front end (front_end.hpp) multiplies in the
//    order the scene format prescribes, which is not GLM's (its mat4 * vec4 adds the column
//    products pairwise), and the reference's own arithmetic is llvmpipe's, written out.
//
// Deliberately does not: build vertices, or choose a viewport.
#pragma once

#include <array>

#include "harness/scene.hpp"

namespace harness {

// A 4x4 matrix as the scene format stores it: column-major, element (row r, column c) at
// [4 * c + r].
using Matrix4 = std::array<float, 16>;
using Vec3 = std::array<float, 3>;

Matrix4 identity_matrix();
// gluPerspective's matrix (GLM's perspective, right-handed, depth to [-1, 1]): vertical field
// of view in degrees, width / height, near and far distances (0 < near < far).
Matrix4 perspective_matrix(float fovy_degrees, float aspect, float near_distance,
                           float far_distance);
// gluLookAt's matrix: the eye at `eye` looking at `centre`, `up` upwards.
Matrix4 look_at_matrix(const Vec3& eye, const Vec3& centre, const Vec3& up);
// A rotation by `degrees` about `axis` (any non-zero length), counter-clockwise looking down
// the axis towards the origin.
Matrix4 rotation_matrix(float degrees, const Vec3& axis);
Matrix4 translation_matrix(const Vec3& offset);
Matrix4 scale_matrix(const Vec3& factors);
// a * b: applying the product applies b first, then a.
Matrix4 multiply(const Matrix4& a, const Matrix4& b);

// Makes `draw` a clip-space draw with `matrix` (its vertices' positions become [x, y, z, 1]
// object coordinates where the file gave fewer than four).
void set_clip_matrix(SceneDraw& draw, const Matrix4& matrix);

}  // namespace harness
