#include "scene/camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace stsv {

mat4 viewFromWorld(const Camera& camera) {
    return glm::lookAtRH(camera.eye, camera.target, camera.up);
}

mat4 clipFromView(const Camera& camera, float aspect, float zNear, float zFar) {
    mat4 proj = glm::perspectiveRH_ZO(glm::radians(camera.fovY), aspect, zNear, zFar);
    proj[1][1] = -proj[1][1]; // Vulkan framebuffer y points down
    return proj;
}

mat4 clipFromViewReversedInfinite(const Camera& camera, float aspect, float zNear) {
    mat4 proj = clipFromView(camera, aspect, zNear, 2.0f * zNear);
    // clip.z = zNear and clip.w = −z_view (glm's columns: [column][row]).
    proj[2][2] = 0.0f;
    proj[3][2] = zNear;
    proj[2][3] = -1.0f;
    proj[3][3] = 0.0f;
    return proj;
}

Ray primaryRay(const Camera& camera, int x, int y, int width, int height) {
    const float tanHalf = std::tan(glm::radians(camera.fovY) * 0.5f);
    const float aspect = float(width) / float(height);
    const float ndcX = (float(x) + 0.5f) / float(width) * 2.0f - 1.0f;
    const float ndcY = (float(y) + 0.5f) / float(height) * 2.0f - 1.0f; // −1 at the top row
    const vec3 dirView(ndcX * tanHalf * aspect, -ndcY * tanHalf, -1.0f);
    const mat3 worldFromView = glm::inverse(mat3(viewFromWorld(camera)));
    return {camera.eye, normalize(worldFromView * dirView)};
}

} // namespace stsv
