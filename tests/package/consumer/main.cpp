// Uses the installed stsv as another engine's tests would: the projective transmittance lookup of
// the STSV paper (Eq. 1-5, volumes/stsv_dh.h) on an S-triangle with known answers. Exit 0 when
// every check holds.
#include "volumes/stsv.h"

#include <cmath>
#include <cstdio>

namespace {

int failures = 0;

void check(bool ok, const char* what) {
    std::printf("%s: %s\n", ok ? "ok  " : "FAIL", what);
    if (!ok) ++failures;
}

// Single precision: the 3x3 inverse and a handful of dot products of values near 1, each rounding
// at 6e-8 relative, stay far inside 1e-5.
bool near(float a, float b) {
    return std::fabs(a - b) < 1e-5f;
}

} // namespace

int main() {
    using namespace stsv;
    // The S-triangle (0,0,1), (1,0,1), (0,1,1) with texture coordinates equal to its (x, y), and a
    // 2x2 alpha texture: the texels of column 0 are opaque, those of column 1 holes.
    Scene scene;
    scene.source = "consumer";
    Texture texture;
    texture.name = "columns";
    texture.width = 2;
    texture.height = 2;
    texture.rgba = {255, 255, 255, 255, 255, 255, 255, 0, 255, 255, 255, 255, 255, 255, 255, 0};
    scene.textures.push_back(texture);
    Material fence;
    fence.name = "fence";
    fence.alphaTexture = 0;
    scene.materials.push_back(fence);
    scene.addTriangle({0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {0, 0}, {1, 0}, {0, 1}, 0);

    // The light frame: centre c above the triangle, s = c + a·T + b·B.
    const vec3 c(0.25f, 0.25f, 2.0f);
    const vec3 T(1, 0, 0);
    const vec3 B(0, 1, 0);
    const StsvTriangle tri = stsvTriangleFor(scene, 0, c);
    const ivec2 size(texture.width, texture.height);

    // A receiver point 1 below the triangle's plane: e = 1 (Eq. 3).
    const StsvPixel px = stsvSetupPixel(tri, vec3(0.2f, 0.2f, 0.0f), c, T, B, SHADOW_T_MIN);
    check(near(px.e, 1.0f), "e is the distance from p to the triangle's plane");

    // s = (0.2, 0.2, 2): the segment meets the plane halfway, at (0.2, 0.2): barycentrics
    // (0.2, 0.2) from h = J(s - p) (Eq. 1), texel (0, 0) (Eq. 4-5), opaque.
    vec3 h = stsvSampleH(px, vec2(-0.05f, -0.05f));
    check(near(h.x / h.z, 0.2f) && near(h.y / h.z, 0.2f), "h.xy / h.z are the barycentrics of the crossing");
    check(near(px.e / h.z, 0.5f), "e / h.z is the crossing's parameter along p->s");
    ivec2 texel;
    bool crosses = stsvSampleCrosses(tri, px, vec2(-0.05f, -0.05f), size, texel);
    check(crosses && texel == ivec2(0, 0), "the sample above p crosses texel (0, 0)");
    check(alphaBlocks(scene.textures[0].alpha(texel.x, texel.y)), "texel (0, 0) blocks");

    // s = (1, 0.2, 2): crossing at (0.6, 0.2), texel (1, 0), a hole: the light passes.
    crosses = stsvSampleCrosses(tri, px, vec2(0.75f, -0.05f), size, texel);
    check(crosses && texel == ivec2(1, 0), "the sample towards +x crosses texel (1, 0)");
    check(!alphaBlocks(scene.textures[0].alpha(texel.x, texel.y)), "texel (1, 0) is a hole");

    // s = (2.2, 2.2, 2): crossing at (1.2, 1.2), outside the triangle.
    check(!stsvSampleCrosses(tri, px, vec2(1.95f, 1.95f), size, texel),
          "a sample past the hypotenuse misses");

    // A point between the triangle and the light: its segments never reach the plane.
    const StsvPixel above = stsvSetupPixel(tri, vec3(0.2f, 0.2f, 1.5f), c, T, B, SHADOW_T_MIN);
    check(!stsvSampleCrosses(tri, above, vec2(-0.05f, -0.05f), size, texel),
          "a point above the triangle is lit");

    std::printf("%d of 9 checks failed\n", failures);
    return failures == 0 ? 0 : 1;
}
