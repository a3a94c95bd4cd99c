#include "shadowmaps/shadow_map.h"

#include "shadowmaps/avsm_dh.h"

#include "core/error.h"
#include "sampling/light_sampling_dh.h"
#include "shadowmaps/depth_grid_dh.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace stsv {

namespace {

/// Square window around the bounds of face points, with a margin of one part in a thousand so
/// that the box's extreme points fall inside the outermost texels.
vec4 squareWindow(vec2 lo, vec2 hi) {
    const vec2 centre = 0.5f * (lo + hi);
    const float half = 0.5f * std::max(hi.x - lo.x, hi.y - lo.y) * 1.001f + 1e-6f;
    return vec4(centre.x - half, centre.y - half, centre.x + half, centre.y + half);
}

ShadowMapView cubeMap(const Light& light, const Bounds& box, vec3 x, vec3 y, vec3 z, int size) {
    ShadowMapView v{};
    v.projection = SHADOW_MAP_CUBE;
    v.origin = light.position;
    v.axisX = x;
    v.axisY = y;
    v.axisZ = z;
    v.size = unsigned(size);
    v.faces = 6u;
    v.window = vec4(-1.0f, -1.0f, 1.0f, 1.0f);
    // A point of the box is at least `distance` from the centre, so at least distance/√3 along
    // the axis of the face that holds it; no point is farther than the farthest corner.
    const float distance = length(clamp(light.position, box.lo, box.hi) - light.position);
    float farthest = 0.0f;
    for (int i = 0; i < 8; ++i) farthest = std::max(farthest, length(box.corner(i) - light.position));
    v.near = std::max(0.99f * distance / std::sqrt(3.0f), 1e-5f * box.diameter());
    v.far = std::max(1.01f * farthest, 2.0f * v.near);
    return v;
}

} // namespace

float shadowLightWidth(const Light& light) {
    switch (light.type) {
    case LIGHT_RECTANGLE:
        return 2.0f * std::max(length(light.axisU), length(light.axisV));
    case LIGHT_DISK:
    case LIGHT_SPHERE:
        return 2.0f * light.radius;
    default:
        return 2.0f * std::tan(light.angularRadius);
    }
}

namespace {

/// Where a box's part in front of the light plane (its twelve edges clipped at axial depth eps)
/// falls on the plane z = 1 of the frame (x, y, z) at `origin`, and its axial depth range.
struct FaceExtent {
    vec2 lo{1e30f}, hi{-1e30f};
    float zlo = 1e30f, zhi = -1e30f;
    bool any = false;
};

FaceExtent perspectiveExtent(const Bounds& box, vec3 origin, vec3 x, vec3 y, vec3 z, float eps) {
    FaceExtent e;
    if (box.empty()) return e;
    auto add = [&](vec3 l) {
        const vec2 s = vec2(l.x, l.y) / l.z;
        e.lo = min(e.lo, s);
        e.hi = max(e.hi, s);
        e.zlo = std::min(e.zlo, l.z);
        e.zhi = std::max(e.zhi, l.z);
        e.any = true;
    };
    for (int a = 0; a < 8; ++a)
        for (int bit = 1; bit < 8; bit <<= 1) {
            if (a & bit) continue;
            const vec3 pa = box.corner(a) - origin, pb = box.corner(a | bit) - origin;
            vec3 la(dot(pa, x), dot(pa, y), dot(pa, z)), lb(dot(pb, x), dot(pb, y), dot(pb, z));
            if (la.z < eps && lb.z < eps) continue;
            if (la.z < eps) la = la + (lb - la) * ((eps - la.z) / (lb.z - la.z));
            if (lb.z < eps) lb = lb + (la - lb) * ((eps - lb.z) / (la.z - lb.z));
            add(la);
            add(lb);
        }
    return e;
}

/// A box's extent across and along an orthographic view (ox, oy across, view along).
FaceExtent orthographicExtent(const Bounds& box, vec3 ox, vec3 oy, vec3 view) {
    FaceExtent e;
    if (box.empty()) return e;
    for (int i = 0; i < 8; ++i) {
        const vec3 p = box.corner(i);
        const vec2 s(dot(p, ox), dot(p, oy));
        e.lo = min(e.lo, s);
        e.hi = max(e.hi, s);
        e.zlo = std::min(e.zlo, dot(p, view));
        e.zhi = std::max(e.zhi, dot(p, view));
        e.any = true;
    }
    return e;
}

} // namespace

ShadowMapView fitShadowMap(const Light& light, const Bounds& box, int size) {
    return fitShadowMapToRegion(light, box, box, size);
}

ShadowMapView fitShadowMapToRegion(const Light& light, const Bounds& receivers, const Bounds& casters,
                                   int size) {
    Bounds all = receivers;
    all.extend(casters);
    if (all.empty()) throw UsageError("shadow map: the scene has no triangles");
    if (size < 1 || size > 16384)
        throw UsageError("shadow map: size must be in 1 … 16384 texels, got " + std::to_string(size));
    // The window holds the casters (every texel outside it would see no blocker); with none, the
    // receivers (the map then blocks nothing). The depth range runs from the nearest caster to the
    // farthest receiver.
    const Bounds& across = casters.empty() ? receivers : casters;
    const float diameter = std::max(all.diameter(), 1e-6f);
    vec3 z = normalize(light.normal);
    vec3 x, y;
    orthonormalBasis(z, x, y);
    if (light.type == LIGHT_RECTANGLE && length(light.axisU) > 0.0f) {
        x = normalize(light.axisU - dot(light.axisU, z) * z);
        y = cross(z, x);
    }
    ShadowMapView v{};
    v.size = unsigned(size);
    v.faces = 1u;
    if (light.type == LIGHT_SPHERE) {
        v = cubeMap(light, all, vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), size);
        v.lightWidth = shadowLightWidth(light);
        return v;
    }
    if (light.type == LIGHT_DIRECTIONAL) {
        // light.normal points towards the light: the map looks the other way.
        const vec3 view = -z;
        vec3 ox, oy;
        orthonormalBasis(view, ox, oy);
        const FaceExtent window = orthographicExtent(across, ox, oy, view);
        const FaceExtent range = orthographicExtent(all, ox, oy, view);
        const float zlo = casters.empty() ? range.zlo : orthographicExtent(casters, ox, oy, view).zlo;
        const float margin = 0.01f * diameter;
        v.projection = SHADOW_MAP_ORTHOGRAPHIC;
        v.axisX = ox;
        v.axisY = oy;
        v.axisZ = view;
        v.origin = (zlo - margin) * view; // depth 0 just before the nearest caster
        v.window = squareWindow(window.lo, window.hi);
        v.near = 0.99f * margin;
        v.far = 1.01f * (range.zhi - zlo + margin);
        v.lightWidth = shadowLightWidth(light);
        return v;
    }
    // Rectangle and disk: a perspective face when the window fits in the angle limit.
    const float eps = 1e-3f * diameter;
    const float limit = std::tan(glm::radians(SHADOW_MAP_MAX_HALF_ANGLE_DEGREES));
    const FaceExtent window = perspectiveExtent(across, light.position, x, y, z, eps);
    const FaceExtent range = perspectiveExtent(all, light.position, x, y, z, eps);
    const FaceExtent nearest =
        casters.empty() ? range : perspectiveExtent(casters, light.position, x, y, z, eps);
    const bool narrow =
        window.any && std::max({-window.lo.x, -window.lo.y, window.hi.x, window.hi.y}) <= limit;
    if (!narrow || !nearest.any) {
        v = cubeMap(light, all, x, y, z, size);
        v.lightWidth = shadowLightWidth(light);
        return v;
    }
    v.projection = SHADOW_MAP_PERSPECTIVE;
    v.origin = light.position;
    v.axisX = x;
    v.axisY = y;
    v.axisZ = z;
    v.window = squareWindow(window.lo, window.hi);
    v.near = 0.99f * nearest.zlo;
    v.far = 1.01f * range.zhi;
    v.lightWidth = shadowLightWidth(light);
    return v;
}

std::size_t shadowMapBytes(const ShadowMapView& view) {
    return std::size_t(view.faces) * std::size_t(view.size) * std::size_t(view.size) * sizeof(float);
}

std::size_t depthGridBytes(const ShadowMapView& view, const ShadowMapSettings& settings) {
    return std::size_t(view.faces) * std::size_t(view.size) * std::size_t(view.size) *
           peelTexelWords(uint(settings.peelBins)) * sizeof(std::uint32_t);
}

std::vector<vec2> poissonDiskTaps(int count, std::uint32_t seed, float* minDistance) {
    if (count < 1) throw UsageError("Poisson-disk taps: count must be at least 1");
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> turn(0.0f, 6.28318530718f);
    // Radii stratified by area: the k-th tap lies on the circle that holds (k + ½)/count of the
    // disk, so a filter of radius R over the taps weighs the disk uniformly. (Dart throwing over
    // the disk leaves the set denser towards the rim, 64 taps: mean r² 0.53 instead of ½, and
    // made PCSS's penumbra 4 % too wide between its 5 % and 95 % levels.) From the centre
    // outwards, each tap takes the best of 32 random angles: the one farthest from the taps placed
    // so far (best-candidate sampling, Mitchell 1991), which spaces the set like a Poisson-disk
    // set (minimum distance about 0.7 of the hexagonal packing's).
    constexpr int CANDIDATES = 32;
    std::vector<vec2> taps;
    taps.reserve(std::size_t(count));
    float closest = 2.0f;
    for (int k = 0; k < count; ++k) {
        const float r = std::sqrt((float(k) + 0.5f) / float(count));
        vec2 best(r, 0.0f);
        float bestDistance = -1.0f;
        for (int c = 0; c < CANDIDATES; ++c) {
            const float a = turn(rng);
            const vec2 q(r * std::cos(a), r * std::sin(a));
            float nearest = 4.0f;
            for (const vec2& t : taps) nearest = std::min(nearest, length(t - q));
            if (nearest > bestDistance) {
                bestDistance = nearest;
                best = q;
            }
        }
        if (!taps.empty()) closest = std::min(closest, bestDistance);
        taps.push_back(best);
    }
    if (minDistance) *minDistance = closest;
    return taps;
}

std::vector<vec2> shadowFilterTaps(const ShadowMapSettings& settings) {
    const bool vpcss = settings.filter == ShadowMapMethod::Vpcss;
    std::vector<vec2> taps = poissonDiskTaps(vpcss ? settings.vpcssTaps : settings.blockerTaps, 0x5eed0001u);
    const std::vector<vec2> filter =
        poissonDiskTaps(vpcss ? settings.vpcssTaps : settings.filterTaps, 0x5eed0002u);
    taps.insert(taps.end(), filter.begin(), filter.end());
    return taps;
}

std::size_t avsmBytes(const ShadowMapView& view, const ShadowMapSettings& settings) {
    const std::size_t texels = std::size_t(view.faces) * view.size * view.size;
    return texels * (4 + 8 * std::size_t(settings.avsmNodes));
}

int filteredChannelCount(const ShadowMapSettings& s) {
    return int(stsv::filteredChannelCount(uint(s.filter), uint(s.csmTerms)));
}

bool filteredUsesMip(const ShadowMapSettings& s) {
    return s.mip != 0 || (isFilteredRepresentation(s.filter) && shadowMapVariant(s.filter).alwaysMip);
}

bool searchesBlockers(const ShadowMapSettings& s) {
    if (s.filter == ShadowMapMethod::None) return false;
    const BlockerSearch search = shadowMapVariant(s.filter).blockers;
    return search == BlockerSearch::Always || (search == BlockerSearch::WithSearchedKernel && s.kernel != 0);
}

bool ShadowMapKnob::readBy(ShadowMapMethod filter) const {
    if (filter == ShadowMapMethod::None) return false;
    const ShadowMapVariant& v = shadowMapVariant(filter);
    switch (readers) {
    case KnobReaders::Every:
        return true;
    case KnobReaders::DepthMaps:
        return v.representation == MapRepresentation::Depths ||
               v.representation == MapRepresentation::Filtered;
    case KnobReaders::Filtered:
        return v.representation == MapRepresentation::Filtered;
    case KnobReaders::SearchedDepths:
        return v.blockers != BlockerSearch::Never && v.representation != MapRepresentation::Transmittance;
    case KnobReaders::Searched:
        return v.blockers != BlockerSearch::Never;
    case KnobReaders::Transmittance:
        return v.representation == MapRepresentation::Transmittance;
    case KnobReaders::Own:
        return std::any_of(v.knobs.begin(), v.knobs.end(),
                           [&](const char* k) { return std::string(k) == name; });
    }
    return false;
}

ShadowFilterParams shadowFilterParams(const ShadowMapSettings& settings) {
    ShadowFilterParams params = settings; // the knobs, as they are
    params.method = uint(settings.filter);
    params.channels = uint(filteredChannelCount(settings));
    params.mip = filteredUsesMip(settings) ? 1u : 0u;
    return params;
}

namespace {

/// The knobs `stsv tune` searches unless told otherwise, with the range and scale it searches
/// each in: the knobs that shape a method's error without changing its cost. Left out are the
/// knobs that trade time or memory for quality, which a search for the least error would only
/// drive to their largest value: the map's, grid's and functions' resolutions (sm_size,
/// peel_size, avsm_size), tap, step, term and node counts (pcss_*_taps, vpcss_taps, peel_bins,
/// peel_max_steps, csm_terms, avsm_nodes), the taps' spread (pcf_max_radius), and sm_fit (the fitted view is
/// finer texels for nothing). The ranges are narrower than the knobs' own where the ends are no candidates
/// for an optimum (a 64-texel bias, a variance floor of 0); a log scale where the effect is multiplicative.
struct TunedKnob {
    const char* name;
    KnobScale scale;
    double lo;
    double hi;
};
constexpr TunedKnob TUNED_KNOBS[] = {
    {"sm_bias", KnobScale::Linear, 0.0, 8.0},          // texels at the receiver
    {"sm_normal_offset", KnobScale::Linear, 0.0, 4.0}, // texels
    {"pcf_world_radius", KnobScale::Log, 0.002, 0.3},  // metres at the receiver: the penumbra's width
    {"fm_kernel", KnobScale::Linear, 0.0, 1.0},        // fixed or searched kernel
    {"fm_world_radius", KnobScale::Log, 0.002, 0.3},   // metres at the receiver
    {"fm_mip", KnobScale::Linear, 0.0, 1.0},           // summed-area table or mips
    {"pcss_max_kernel", KnobScale::Log, 4.0, 4096.0},  // texels
    {"pcss_max_search", KnobScale::Log, 4.0, 1024.0},  // texels
    {"vsm_min_variance", KnobScale::Log, 1e-8, 1e-2},
    {"vsm_bleed", KnobScale::Linear, 0.0, 0.9},
    {"esm_c", KnobScale::Log, 5.0, 88.0},
    {"evsm_positive", KnobScale::Log, 2.0, 42.0},
    {"evsm_negative", KnobScale::Log, 1.0, 42.0},
    {"msm_bias", KnobScale::Log, 1e-8, 1e-2},
    {"csm_damp", KnobScale::Linear, 0.0, 1.0},
};

/// `knobs` with TUNED_KNOBS' search set on theirs; std::logic_error (a bug) for a name that is
/// no knob or a range outside the knob's.
std::vector<ShadowMapKnob> withTunedKnobs(std::vector<ShadowMapKnob> knobs) {
    for (const TunedKnob& t : TUNED_KNOBS) {
        const auto knob = std::find_if(knobs.begin(), knobs.end(),
                                       [&](const ShadowMapKnob& k) { return std::string(k.name) == t.name; });
        if (knob == knobs.end() || t.lo < knob->min || t.hi > knob->max || !(t.lo < t.hi) ||
            (t.scale == KnobScale::Log && t.lo <= 0.0))
            throw std::logic_error(std::string("tuned knob ") + t.name + ": no such knob, or a bad range");
        knob->search = {true, t.scale, t.lo, t.hi};
    }
    return knobs;
}

} // namespace

const std::vector<ShadowMapKnob>& shadowMapKnobs() {
    using K = KnobReaders;
    using S = ShadowMapSettings;
    static const std::vector<ShadowMapKnob> knobs = {
        {"sm_size", 256, 8192, true, "shadow map texels per face edge (32-bit linear depth)", K::DepthMaps,
         &S::size},
        {"sm_fit", 0, 1, true,
         "what the map is fitted to: 0 the scene box, 1 the receivers in view and the casters between "
         "them and the light",
         K::Every, &S::fit},
        {"sm_bias", 0, 64, false, "constant depth bias, in texels at the receiver", K::Every, &S::bias},
        {"sm_normal_offset", 0, 64, false, "receiver moved along its normal before the lookup, in texels",
         K::Every, &S::normalOffset},
        {"pcf_world_radius", 0, 10, false,
         "kernel half-width at the receiver, in world units (metres); converted to texels per pixel", K::Own,
         &S::pcfWorldRadius},
        {"pcf_max_radius", 1, 128, true,
         "taps either side at most, one texel apart; a wider kernel spreads them (the stats count the "
         "pixels where they are more than three texels apart)",
         K::Own, &S::pcfMaxRadius},
        {"fm_kernel", 0, 1, true,
         "kernel size: 0 fm_world_radius everywhere, 1 per pixel from PCSS's blocker search", K::Filtered,
         &S::kernel},
        {"fm_world_radius", 0, 10, false,
         "fixed kernel half-width at the receiver, in world units (metres); converted to texels per pixel",
         K::Filtered, &S::worldRadius},
        {"fm_mip", 0, 1, true,
         "the average: 0 a summed-area table, 1 bilinear taps of a mip pyramid (ESM, EVSM: always mip)",
         K::Filtered, &S::mip},
        {"pcss_blocker_taps", 1, 256, true, "Poisson-disk taps of the blocker search", K::SearchedDepths,
         &S::blockerTaps},
        {"pcss_filter_taps", 1, 256, true, "Poisson-disk taps of the filter", K::Own, &S::filterTaps},
        {"pcss_max_kernel", 1, 8192, false,
         "largest filter radius, texels (the stats count the pixels it clamps)", K::Searched, &S::maxKernel},
        {"pcss_max_search", 1, 8192, false,
         "largest blocker-search radius, texels (the stats count the pixels it clamps)", K::Searched,
         &S::maxSearch},
        {"vsm_min_variance", 0, 0.01, false, "smallest variance of the normalised depth (VSM, EVSM)", K::Own,
         &S::minVariance},
        {"vsm_bleed", 0, 0.99, false, "light-bleeding reduction: bounds below it become 0 (0: off)", K::Own,
         &S::bleed},
        {"esm_c", 1, 88, false, "exponent c of exp(c z) (below ln FLT_MAX = 88.7)", K::Own, &S::esmC},
        {"evsm_positive", 1, 42, false, "positive warp exponent (its square must fit a float)", K::Own,
         &S::evsmPositive},
        {"evsm_negative", 1, 42, false, "negative warp exponent", K::Own, &S::evsmNegative},
        {"msm_bias", 0, 0.01, false, "moment bias alpha towards (1/2, 1/2, 1/2, 1/2)", K::Own, &S::msmBias},
        {"csm_terms", 1, 16, true, "Fourier terms M (2M values per texel)", K::Own, &S::csmTerms},
        {"csm_damp", 0, 1, true, "Lanczos sigma factors on the terms against ringing", K::Own, &S::csmDamp},
        {"peel_size", 16, 4096, true, "depth grid texels per face edge (4 (2 + 2 peel_bins) bytes a texel)",
         K::Own, &S::peelSize},
        {"peel_bins", 1, 32, true, "subintervals of each grid texel's depth range", K::Own, &S::peelBins},
        {"peel_max_steps", 1, 1024, true,
         "most march steps a light-sample ray takes (a texel a step; longer steps past it, counted in "
         "--stats)",
         K::Own, &S::peelMaxSteps},
        {"avsm_size", 16, 8192, true,
         "transmittance-function texels per face edge (4 + 8 avsm_nodes bytes a texel)", K::Transmittance,
         &S::avsmSize},
        {"avsm_nodes", 1, double(AVSM_MAX_NODES), true,
         "nodes of each texel's transmittance function (the least important is dropped beyond)",
         K::Transmittance, &S::avsmNodes},
        {"vpcss_taps", 1, 256, true, "Poisson-disk taps of the blocker search and of the filter", K::Own,
         &S::vpcssTaps},
    };
    static const std::vector<ShadowMapKnob> tuned = withTunedKnobs(knobs);
    return tuned;
}

const char* retiredShadowMapKnob(const std::string& name) {
    if (name == "pcf_radius")
        return "pcf_radius (a kernel radius in texels) was replaced by pcf_world_radius, the kernel's "
               "half-width in world units (metres) at the receiver: pcf_radius=r on a map whose texels are T "
               "metres at the receiver (--stats: texel_world_median) is pcf_world_radius=(r+0.5)*T";
    if (name == "fm_radius")
        return "fm_radius (a kernel radius in texels) was replaced by fm_world_radius, the kernel's "
               "half-width in world units (metres) at the receiver: fm_radius=r on a map whose texels are T "
               "metres at the receiver (--stats: texel_world_median) is fm_world_radius=(r+0.5)*T";
    return nullptr;
}

namespace {

const ShadowMapKnob& knobNamed(const char* name) {
    const auto& knobs = shadowMapKnobs();
    const auto knob = std::find_if(knobs.begin(), knobs.end(),
                                   [&](const ShadowMapKnob& k) { return std::string(k.name) == name; });
    if (knob == knobs.end()) throw std::logic_error(std::string("no shadow-map knob ") + name);
    return *knob;
}

} // namespace

ShadowMapSettings defaultShadowMapSettings(ShadowMapMethod filter) {
    ShadowMapSettings s;
    s.filter = filter;
    if (filter == ShadowMapMethod::None) return s;
    for (const auto& [knob, value] : shadowMapVariant(filter).defaults) knobNamed(knob).set(s, value);
    return s;
}

ShadowMapSettings shadowMapSettingsFrom(ShadowMapMethod filter, const std::map<std::string, double>& params) {
    ShadowMapSettings s = defaultShadowMapSettings(filter);
    for (const auto& [key, value] : params) {
        const std::string& name = key; // a lambda may not capture a structured binding (clang 14)
        const auto& knobs = shadowMapKnobs();
        const auto knob = std::find_if(knobs.begin(), knobs.end(), [&](const ShadowMapKnob& k) {
            return k.readBy(filter) && name == k.name;
        });
        if (knob == knobs.end()) {
            if (const char* why = retiredShadowMapKnob(name)) throw UsageError(why);
            throw UsageError("shadow maps have no parameter '" + name + "' for this method");
        }
        knob->set(s, value);
    }
    return s;
}

} // namespace stsv
