// authoring.cpp: GLM's matrices in the scene format's layout (authoring.hpp).
#include "harness/authoring.hpp"

#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <stdexcept>

namespace harness {
namespace {

// GLM stores column-major too: m[c][r] is column c, row r.
Matrix4 from_glm(const glm::mat4& m) {
    Matrix4 out{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) out[static_cast<std::size_t>(4 * c + r)] = m[c][r];
    return out;
}

glm::mat4 to_glm(const Matrix4& a) {
    glm::mat4 m(1.0f);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] = a[static_cast<std::size_t>(4 * c + r)];
    return m;
}

glm::vec3 to_glm(const Vec3& v) {
    return {v[0], v[1], v[2]};
}

void require(bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(what);
}

}  // namespace

Matrix4 identity_matrix() {
    return from_glm(glm::mat4(1.0f));
}

Matrix4 perspective_matrix(float fovy_degrees, float aspect, float near_distance,
                           float far_distance) {
    require(fovy_degrees > 0.0f && fovy_degrees < 180.0f,
            "perspective_matrix: the field of view must lie in (0, 180) degrees");
    require(aspect > 0.0f && std::isfinite(aspect), "perspective_matrix: aspect must be > 0");
    require(near_distance > 0.0f && far_distance > near_distance && std::isfinite(far_distance),
            "perspective_matrix: need 0 < near < far");
    return from_glm(
        glm::perspective(glm::radians(fovy_degrees), aspect, near_distance, far_distance));
}

Matrix4 look_at_matrix(const Vec3& eye, const Vec3& centre, const Vec3& up) {
    const glm::vec3 f = to_glm(centre) - to_glm(eye);
    require(glm::length(f) > 0.0f, "look_at_matrix: the eye is at the centre");
    require(glm::length(glm::cross(f, to_glm(up))) > 0.0f,
            "look_at_matrix: up is parallel to the line of sight");
    return from_glm(glm::lookAt(to_glm(eye), to_glm(centre), to_glm(up)));
}

Matrix4 rotation_matrix(float degrees, const Vec3& axis) {
    require(glm::length(to_glm(axis)) > 0.0f, "rotation_matrix: the axis has length zero");
    return from_glm(glm::rotate(glm::mat4(1.0f), glm::radians(degrees), to_glm(axis)));
}

Matrix4 translation_matrix(const Vec3& offset) {
    return from_glm(glm::translate(glm::mat4(1.0f), to_glm(offset)));
}

Matrix4 scale_matrix(const Vec3& factors) {
    return from_glm(glm::scale(glm::mat4(1.0f), to_glm(factors)));
}

Matrix4 multiply(const Matrix4& a, const Matrix4& b) {
    return from_glm(to_glm(a) * to_glm(b));
}

void set_clip_matrix(SceneDraw& draw, const Matrix4& matrix) {
    draw.space = VertexSpace::Clip;
    draw.matrix = matrix;
    for (auto& v : draw.vertices) {
        if (v.position_size < 4) {
            if (v.position_size < 3) v.position[2] = 0.0f;
            v.position[3] = 1.0f;
        }
        v.position_size = 4;
    }
}

}  // namespace harness
