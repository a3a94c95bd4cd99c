// `stsv tune`: searches an image-based method's knobs for the least error against the converged
// references of training scenes (a coarse grid per knob, then a local refinement), and reports
// the best knobs beside the defaults on those scenes and on held-out ones; the knobs files that
// `compare --knobs` reads.
//
// The search, per method (deterministic: the same arguments try the same knobs in the same order):
//  1. the defaults (with the --param values) are rendered first; their errors are the unit of
//     the objective, which is then 1;
//  2. coarse grid, one knob at a time in the order of the knob list: GRID_POINTS values evenly
//     spaced over its search range (in log(value) for a log-scale knob; every value of an integer
//     knob with no more), the other knobs at the best point so far; the best of them is kept
//     when it beats the best point so far;
//  3. refinement: rounds of, per knob not exhausted by its grid, the values half a grid step on
//     either side of the best point's, kept when they beat it; the step halves after each round,
//     REFINE_ROUNDS rounds.
// A point beats another only with a strictly lower objective, so the defaults are reported
// unless a point does better on the training scenes. Every render counts against --budget
// (the defaults' too); the search ends where the next point would pass it.
//
// The objective is the mean over the training scenes of each scene's error divided by the
// defaults' error on that scene (plus ERROR_FLOOR on both sides, for a scene the defaults get
// exactly right). Ratios rather than the errors' plain mean: the scenes' errors differ in scale
// (a scene of wide penumbrae or many pixels in shadow has a larger RMSE at any knob), and a plain
// mean would tune for the worst scene alone; the ratio weighs each scene by its relative gain.
//
// --objective worst asks for the knobs nearest every scene's own best at once, the measure of
// fair defaults: each training scene is searched alone first (the search above, its own budget),
// then the scenes together for the least worst ratio of a scene's error to its own best (plus
// ERROR_FLOOR on both sides). The defaults' objective is then their worst ratio, not 1. A ratio
// below 1 on some scene means the joint search found a better point there than that scene's own.
#include "cli/cli_util.h"
#include "cli/compare_report.h"
#include "cli/converged_reference.h"
#include "cli/subcommands.h"

#include "core/error.h"
#include "core/files.h"
#include "core/progress.h"
#include "core/timer.h"
#include "core/version.h"
#include "render/renderer.h"
#include "sampling/light_bounds.h"
#include "scene/load.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>

namespace stsv {

namespace {

/// Values per knob of the coarse grid.
constexpr int GRID_POINTS = 5;
/// Halvings of the refinement's step (from half a grid step: 1/8 of the range, down to 1/64).
constexpr int REFINE_ROUNDS = 4;
/// Added to a scene's error and to the defaults' before their ratio (visibility RMSE units:
/// far below any converged reference's own noise).
constexpr double ERROR_FLOOR = 1e-6;
/// Significant digits of the values tried of a continuous knob (the printed and written values
/// are the values rendered).
constexpr int SIGNIFICANT_DIGITS = 4;

std::string formatNumber(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

std::string toString(KnobScale scale) {
    return scale == KnobScale::Log ? "log" : "linear";
}

/// `value` rounded to SIGNIFICANT_DIGITS significant digits.
double roundSignificant(double value) {
    if (value == 0.0 || !std::isfinite(value)) return value;
    const double magnitude = std::floor(std::log10(std::abs(value)));
    const double scale = std::pow(10.0, double(SIGNIFICANT_DIGITS - 1) - magnitude);
    return std::round(value * scale) / scale;
}

/// One knob the search varies.
struct SearchedKnob {
    std::string name;
    KnobSearch range;
    bool integer = false;
    double defaultValue = 0.0; ///< the method's default, or its --param value
    bool exhaustive = false;   ///< the grid tried every value (an integer knob of few values)

    /// The value at position u in [0, 1] of the range.
    double valueAt(double u) const {
        u = std::clamp(u, 0.0, 1.0);
        double v = range.scale == KnobScale::Log ? range.lo * std::pow(range.hi / range.lo, u)
                                                 : range.lo + u * (range.hi - range.lo);
        v = integer ? std::round(v) : roundSignificant(v);
        return std::clamp(v, range.lo, range.hi);
    }
    /// The position of `value` in the range, clamped to [0, 1].
    double positionOf(double value) const {
        if (range.scale == KnobScale::Log)
            return value <= range.lo
                       ? 0.0
                       : std::clamp(std::log(value / range.lo) / std::log(range.hi / range.lo), 0.0, 1.0);
        return std::clamp((value - range.lo) / (range.hi - range.lo), 0.0, 1.0);
    }
    std::vector<double> grid() const {
        std::vector<double> values;
        if (exhaustive) {
            for (double v = range.lo; v <= range.hi; v += 1.0) values.push_back(v);
            return values;
        }
        for (int i = 0; i < GRID_POINTS; ++i) {
            const double v = valueAt(double(i) / double(GRID_POINTS - 1));
            if (std::find(values.begin(), values.end(), v) == values.end()) values.push_back(v);
        }
        return values;
    }
};

/// A training or held-out scene with its converged reference.
struct TuneScene {
    std::string spec;
    Scene scene;
    ImageF converged; ///< visibility, display values
    /// The pixels the error counts, from the G-buffer of the first frame rendered of the scene
    /// (every frame of a backend sees the same G-buffer; compare takes its --against frame's).
    mutable std::optional<LightFacingMask> facing;
};

/// The error tune minimises on one scene, the figure compare ranks by: the frame's visibility
/// RMSE (display units) over the light-facing pixels, against the scene's converged reference.
/// Pixels facing away from every light change nothing in the lit image, and counting them
/// would tune the filtered maps for the light bleeding there (docs/user-guide.md, compare). A
/// scene where no pixel faces a light counts every pixel (its facing_pixels, in --json, is 0).
double tuneError(const Frame& frame, const TuneScene& s) {
    const ImageF visibility = toDisplay(frame.visibility, false);
    if (!s.facing)
        s.facing = lightFacingMask(frame.gbuffer, s.scene.lights, farDistanceFor(s.scene.bounds()),
                                   visibility.width, visibility.height);
    if (s.facing->facing == 0) return compareImages(visibility, s.converged).rmse;
    return compareImagesWhere(visibility, s.converged, s.facing->selected).rmse;
}
constexpr const char* ERROR_NAME =
    "visibility RMSE over the light-facing pixels against the converged reference";

const char* objectiveName(bool worst) {
    return worst ? "worst over the training scenes of the error divided by the scene's own best (each "
                   "scene searched alone first)"
                 : "mean over the training scenes of the error divided by the defaults' error";
}

/// "name=value name=value" of `values` (the searched knobs', in order).
std::string describePoint(const std::vector<SearchedKnob>& knobs, const std::vector<double>& values) {
    std::string text;
    for (std::size_t i = 0; i < knobs.size(); ++i)
        text += (text.empty() ? "" : " ") + knobs[i].name + "=" + formatNumber(values[i]);
    return text;
}

/// --knob items: NAME or NAME=LO:HI, each possibly a comma-separated list.
struct KnobRequest {
    std::string name;
    std::optional<std::pair<double, double>> range;
    std::string item; ///< as given
};

std::vector<KnobRequest> parseKnobRequests(const std::vector<std::string>& items) {
    std::vector<KnobRequest> requests;
    for (const std::string& given : items)
        for (const std::string& item : splitList(given, "--knob")) {
            KnobRequest r;
            r.item = item;
            const std::size_t eq = item.find('=');
            r.name = item.substr(0, eq);
            if (r.name.empty()) throw UsageError("--knob '" + item + "': no knob name (NAME or NAME=LO:HI)");
            if (eq != std::string::npos) {
                const std::string range = item.substr(eq + 1);
                const std::size_t colon = range.find(':');
                auto number = [&](const std::string& text) {
                    char* end = nullptr;
                    const double v = std::strtod(text.c_str(), &end);
                    if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
                        throw UsageError("--knob '" + item + "': '" + text +
                                         "' is not a number (NAME=LO:HI, e.g. sm_bias=0:4)");
                    return v;
                };
                if (colon == std::string::npos)
                    throw UsageError("--knob '" + item + "': the range is LO:HI (e.g. sm_bias=0:4)");
                r.range = std::make_pair(number(range.substr(0, colon)), number(range.substr(colon + 1)));
            }
            for (const KnobRequest& other : requests)
                if (other.name == r.name) throw UsageError("--knob names " + r.name + " twice");
            requests.push_back(r);
        }
    return requests;
}

/// The knob of `filter` named `name` in the one list, or null.
const ShadowMapKnob* mapKnob(ShadowMapMethod filter, const std::string& name) {
    for (const ShadowMapKnob& k : shadowMapKnobs())
        if (k.readBy(filter) && name == k.name) return &k;
    return nullptr;
}

/// The names given by --param items.
std::set<std::string> paramNames(const std::vector<std::string>& items) {
    std::set<std::string> names;
    for (const std::string& item : items) names.insert(item.substr(0, item.find('=')));
    return names;
}

/// The knobs the search of `method` varies: the --knob ones it reads, else its tunable ones not
/// fixed by --param. UsageError for a knob both searched and fixed, a bad range, or none left.
std::vector<SearchedKnob> searchedKnobs(const MethodInfo& method, const MethodParams& fixed,
                                        const std::vector<KnobRequest>& requests,
                                        const std::set<std::string>& given) {
    std::vector<SearchedKnob> knobs;
    auto add = [&](const ShadowMapKnob& k, KnobSearch range) {
        SearchedKnob s;
        s.name = k.name;
        s.range = range;
        s.integer = k.integer;
        s.defaultValue = fixed.at(k.name);
        s.exhaustive = k.integer && range.hi - range.lo + 1.0 <= double(GRID_POINTS);
        knobs.push_back(s);
    };
    if (!requests.empty()) {
        for (const KnobRequest& r : requests) {
            const ShadowMapKnob* k = mapKnob(method.shadowMap, r.name);
            if (!k) continue; // another method's (runTune checked that some method reads it)
            if (given.count(r.name))
                throw UsageError("--knob " + r.name + " and --param " + r.name +
                                 ": a knob is either searched (--knob) or fixed (--param), not both");
            KnobSearch range = k->searchRange();
            if (r.range) {
                range.lo = r.range->first;
                range.hi = r.range->second;
                if (!(range.lo < range.hi) || range.lo < k->min || range.hi > k->max)
                    throw UsageError("--knob '" + r.item + "': the range must be LO < HI within " + r.name +
                                     "'s [" + formatNumber(k->min) + ", " + formatNumber(k->max) + "]");
                if (range.scale == KnobScale::Log && range.lo <= 0.0) range.scale = KnobScale::Linear;
                if (k->integer && std::floor(range.lo) != range.lo)
                    throw UsageError("--knob '" + r.item + "': " + r.name + " is an integer knob");
            }
            add(*k, range);
        }
        if (knobs.empty())
            throw UsageError("--knob names no knob of " + method.name + " (its knobs: " + [&] {
                std::string list;
                for (const MethodKnob& k : method.knobs) list += (list.empty() ? "" : ", ") + k.name;
                return list;
            }() + ")");
        return knobs;
    }
    std::string costKnobs;
    for (const ShadowMapKnob& k : shadowMapKnobs()) {
        if (!k.readBy(method.shadowMap)) continue;
        if (k.search.tunable && !given.count(k.name))
            add(k, k.search);
        else if (!k.search.tunable)
            costKnobs += (costKnobs.empty() ? "" : ", ") + std::string(k.name);
    }
    if (knobs.empty())
        throw UsageError("tune: " + method.name +
                         " has no knob left to search: its tunable knobs are fixed by " +
                         "--param, or it has none (" + (costKnobs.empty() ? "none" : costKnobs) +
                         " trade time or memory for quality); name the knobs to search with --knob NAME");
    return knobs;
}

/// A point of the search and its errors per training scene.
struct Evaluation {
    std::vector<double> values;
    std::vector<double> errors;
    double objective = 1.0;
};

/// (error + floor) / (unit + floor): a scene's error in the objective's unit.
double errorRatio(double error, double unit) {
    return (error + ERROR_FLOOR) / (unit + ERROR_FLOOR);
}

/// Without `ownBests`, the mean over the scenes of each error over the defaults'; with them, the
/// worst over the scenes of each error over the scene's own best.
double objectiveOf(const std::vector<double>& errors, const std::vector<double>& defaults,
                   const std::vector<double>& ownBests) {
    if (!ownBests.empty()) {
        double worst = 0.0;
        for (std::size_t i = 0; i < errors.size(); ++i)
            worst = std::max(worst, errorRatio(errors[i], ownBests[i]));
        return worst;
    }
    double sum = 0.0;
    for (std::size_t i = 0; i < errors.size(); ++i) sum += errorRatio(errors[i], defaults[i]);
    return sum / double(errors.size());
}

/// Loads a scene and its converged reference (cached as compare caches it).
TuneScene loadTuneScene(const std::string& spec, const SceneOptions& sets, const RenderOptions& against,
                        int frames, bool useCache, bool quiet) {
    TuneScene s;
    s.spec = spec;
    s.scene = loadScene(spec, sets);
    printSceneWarnings(s.scene, quiet);
    checkFrameMemory(against, s.scene);
    ConvergedRequest request;
    request.scene = &s.scene;
    request.spec = spec;
    request.sceneSets = sets;
    request.options = against;
    request.frames = frames;
    request.useCache = useCache;
    request.cacheDir = convergedCacheDirectory();
    request.render = [&](const RenderOptions& o) { return renderFrame(s.scene, o); };
    const ConvergedReference converged = convergedReference(request);
    for (const std::string& m : converged.messages) std::fprintf(stderr, "note: %s\n", m.c_str());
    if (!quiet)
        std::fprintf(stderr, "%s: converged reference (%d x %d samples per pixel), cache %s\n",
                     printable(spec).c_str(), frames, against.samples, toString(converged.cache).c_str());
    s.converged = toDisplay(converged.images.visibility, false);
    return s;
}

/// The search and its results for one method.
struct MethodResult {
    MethodBackend mb;
    std::vector<SearchedKnob> knobs;
    MethodParams fixed; ///< every knob of the method: defaults and --param values
    std::set<std::string> given;
    Evaluation defaults;
    Evaluation best;
    /// --objective worst: each training scene's least error, from a search on it alone (the
    /// objective's unit per scene); empty for --objective mean
    std::vector<double> ownBests;
    int ownRenders = 0; ///< the renders of those searches
    std::vector<double> heldOutDefault, heldOutBest;
    int renders = 0; ///< the search's
    int heldOutRenders = 0;
    int evaluations = 0;
    bool budgetSpent = false;
    double seconds = 0.0;
    std::set<std::string> warnings;

    MethodParams paramsAt(const std::vector<double>& values) const {
        MethodParams p = fixed;
        for (std::size_t i = 0; i < knobs.size(); ++i) p[knobs[i].name] = values[i];
        return p;
    }
};

class Search {
  public:
    Search(MethodResult& result, const std::vector<TuneScene>& training, const RenderOptions& base,
           int budget, bool quiet)
        : m_r(result), m_training(training), m_base(base), m_budget(budget), m_quiet(quiet) {}

    void run() {
        std::vector<double> defaults;
        for (const SearchedKnob& k : m_r.knobs) defaults.push_back(k.defaultValue);
        const std::optional<Evaluation> first = evaluate(defaults);
        if (!first)
            throw UsageError("--budget " + std::to_string(m_budget) +
                             " is less than one render per "
                             "training scene (" +
                             std::to_string(m_training.size()) + ")");
        m_r.defaults = m_r.best = *first;
        // 2. the coarse grid, one knob at a time.
        for (std::size_t k = 0; k < m_r.knobs.size() && !m_r.budgetSpent; ++k)
            for (double v : m_r.knobs[k].grid()) {
                if (!tryValue(k, v)) break;
            }
        // 3. refinement around the best point, the step halving each round.
        double step = 0.5 / double(GRID_POINTS - 1);
        for (int round = 0; round < REFINE_ROUNDS && !m_r.budgetSpent; ++round, step *= 0.5)
            for (std::size_t k = 0; k < m_r.knobs.size() && !m_r.budgetSpent; ++k) {
                const SearchedKnob& knob = m_r.knobs[k];
                if (knob.exhaustive) continue;
                const double u = knob.positionOf(m_r.best.values[k]);
                for (double candidate : {knob.valueAt(u - step), knob.valueAt(u + step)})
                    if (!tryValue(k, candidate)) break;
            }
    }

  private:
    /// The best point with knob k at `value`, evaluated; false when the budget stops the search.
    bool tryValue(std::size_t k, double value) {
        std::vector<double> point = m_r.best.values;
        if (point[k] == value) return true;
        point[k] = value;
        const std::optional<Evaluation> e = evaluate(point);
        if (!e) return false;
        if (e->objective < m_r.best.objective) m_r.best = *e;
        return true;
    }

    /// Renders `values` on every training scene (once per point); nullopt when that would pass
    /// the budget.
    std::optional<Evaluation> evaluate(const std::vector<double>& values) {
        if (const auto it = m_seen.find(values); it != m_seen.end()) return it->second;
        if (m_r.renders + int(m_training.size()) > m_budget) {
            m_r.budgetSpent = true;
            return std::nullopt;
        }
        Evaluation e;
        e.values = values;
        RenderOptions o = m_base;
        o.params = m_r.paramsAt(values);
        for (const TuneScene& s : m_training) {
            checkFrameMemory(o, s.scene);
            const Frame frame = renderFrame(s.scene, o);
            for (const std::string& w : frameWarnings(frame.stats)) m_r.warnings.insert(s.spec + ": " + w);
            e.errors.push_back(tuneError(frame, s));
            ++m_r.renders;
        }
        // The defaults are the mean objective's unit; the worst one measures them too.
        e.objective =
            m_seen.empty() && m_r.ownBests.empty()
                ? 1.0
                : objectiveOf(e.errors, m_seen.empty() ? e.errors : m_r.defaults.errors, m_r.ownBests);
        ++m_r.evaluations;
        m_seen.emplace(values, e);
        if (!m_quiet) {
            const double best = m_seen.size() == 1 ? e.objective : std::min(e.objective, m_r.best.objective);
            std::fprintf(stderr, "tune %s: render %d of at most %d: %s: %s %s (best %s)\n",
                         toString(m_r.mb).c_str(), m_r.renders, m_budget,
                         describePoint(m_r.knobs, values).c_str(), formatFixed(e.objective, 4).c_str(),
                         m_r.ownBests.empty() ? "of the defaults' error"
                                              : "of its own best on the worst scene",
                         formatFixed(best, 4).c_str());
        }
        return e;
    }

    MethodResult& m_r;
    const std::vector<TuneScene>& m_training;
    RenderOptions m_base;
    int m_budget;
    bool m_quiet;
    std::map<std::vector<double>, Evaluation> m_seen;
};

/// The scenes of --scenes or --validate: each value may be a comma-separated list.
std::vector<std::string> sceneList(const std::vector<std::string>& values, const std::string& option) {
    std::vector<std::string> specs;
    for (const std::string& v : values)
        for (const std::string& spec : splitList(v, option)) {
            if (std::find(specs.begin(), specs.end(), spec) != specs.end())
                throw UsageError(option + " names " + spec + " twice");
            specs.push_back(spec);
        }
    return specs;
}

/// A knob's value as JSON: an integer knob's as an integer; a default held as a float (0.03f) as
/// the shortest decimal that reads back as that float (0.03, not 0.029999999329447746).
nlohmann::json knobValueJson(Method method, const std::string& name, double value) {
    const MethodKnob* k = methodInfo(method).knob(name);
    if (k && k->integer) return std::int64_t(value);
    const float f = float(value);
    if (double(f) != value || !std::isfinite(f)) return value;
    for (int digits = 1; digits <= 9; ++digits) {
        char text[32];
        std::snprintf(text, sizeof text, "%.*g", digits, double(f));
        const double shortest = std::strtod(text, nullptr);
        if (float(shortest) == f) return shortest;
    }
    return value;
}

/// The searched knobs at `values` and the --param ones: what compare --knobs sets.
nlohmann::json knobsJson(Method method, const std::vector<SearchedKnob>& knobs,
                         const std::vector<double>& values, const MethodParams& fixed,
                         const std::set<std::string>& given) {
    nlohmann::json j = nlohmann::json::object();
    for (std::size_t i = 0; i < knobs.size(); ++i)
        j[knobs[i].name] = knobValueJson(method, knobs[i].name, values[i]);
    for (const std::string& name : given)
        if (fixed.count(name)) j[name] = knobValueJson(method, name, fixed.at(name));
    return j;
}

void printResult(const MethodResult& r, const std::vector<TuneScene>& training,
                 const std::vector<TuneScene>& heldOut, int budget) {
    const bool improved = r.best.objective < r.defaults.objective;
    std::printf("\n%s: %d renders of the search (budget %d%s)%s, %d of the held-out scenes, %.1f s\n",
                toString(r.mb).c_str(), r.renders, budget, r.budgetSpent ? ", spent" : "",
                r.ownBests.empty() ? ""
                                   : (", " + std::to_string(r.ownRenders) + " of the scenes' own").c_str(),
                r.heldOutRenders, r.seconds);
    ReportTable knobs;
    knobs.header = {"knob", "searched", "scale", "default", "best"};
    for (std::size_t i = 0; i < r.knobs.size(); ++i) {
        const SearchedKnob& k = r.knobs[i];
        knobs.rows.push_back({k.name, formatNumber(k.range.lo) + " to " + formatNumber(k.range.hi),
                              toString(k.range.scale) + (k.integer ? ", integer" : ""),
                              formatNumber(k.defaultValue), formatNumber(r.best.values[i])});
    }
    std::string fixed;
    for (const std::string& name : r.given)
        if (r.fixed.count(name))
            fixed += (fixed.empty() ? "" : ", ") + name + "=" + formatNumber(r.fixed.at(name));
    if (!fixed.empty()) knobs.note = "fixed by --param: " + fixed;
    std::printf("%s", formatTextTable(knobs).c_str());
    ReportTable errors;
    errors.caption = std::string(ERROR_NAME) + ":";
    const bool worst = !r.ownBests.empty();
    errors.header = {"scene", "set", "defaults", "best", "best/defaults"};
    if (worst) errors.header.insert(errors.header.end(), {"own best", "defaults/own", "best/own"});
    for (std::size_t i = 0; i < training.size() + heldOut.size(); ++i) {
        const bool train = i < training.size();
        const std::size_t k = train ? i : i - training.size();
        const double d = train ? r.defaults.errors[k] : r.heldOutDefault[k];
        const double b = train ? r.best.errors[k] : r.heldOutBest[k];
        std::vector<std::string> row = {(train ? training[k] : heldOut[k]).spec,
                                        train ? "training" : "held out", formatFixed(d, 5), formatFixed(b, 5),
                                        formatFixed(errorRatio(b, d), 4)};
        if (worst && train)
            row.insert(row.end(),
                       {formatFixed(r.ownBests[k], 5), formatFixed(errorRatio(d, r.ownBests[k]), 4),
                        formatFixed(errorRatio(b, r.ownBests[k]), 4)});
        else if (worst)
            row.insert(row.end(), {"", "", ""});
        errors.rows.push_back(row);
    }
    if (worst)
        errors.note = "objective (worst over the training scenes of error/own best): defaults " +
                      formatFixed(r.defaults.objective, 4) + ", best " + formatFixed(r.best.objective, 4) +
                      (improved ? "" : "; no point beat the defaults");
    else
        errors.note = improved ? "objective (mean of best/defaults over the training scenes): " +
                                     formatFixed(r.best.objective, 4)
                               : "no point beat the defaults on the training scenes: the defaults are the "
                                 "best knobs found";
    std::printf("%s", formatTextTable(errors).c_str());
}

} // namespace

namespace {

/// The methods tuned: image-based ones (the others have no knobs), each once, on `backend`.
std::vector<MethodBackend> tunedMethods(const std::string& list, Backend backend) {
    std::vector<MethodBackend> methods;
    for (const std::string& name : splitList(list, "METHOD")) {
        const MethodInfo& m = findMethod(name);
        if (m.family != MethodFamily::ImageBased) {
            std::string imageBased;
            for (const MethodInfo& i : methodTable())
                if (i.family == MethodFamily::ImageBased)
                    imageBased += (imageBased.empty() ? "" : ", ") + i.name;
            throw UsageError("tune: method " + m.name +
                             " has no knobs to tune; tune searches the knobs of the "
                             "image-based methods (" +
                             imageBased + ")");
        }
        checkBackendSupports(m.id, backend);
        for (const MethodBackend& other : methods)
            if (other.method == m.id) throw UsageError("tune: METHOD names " + m.name + " twice");
        methods.push_back({m.id, backend});
    }
    if (methods.empty()) throw UsageError("tune: no METHOD given");
    return methods;
}

/// Every --knob names a knob of one of the methods at least.
void checkKnobRequests(const std::vector<KnobRequest>& requests, const std::vector<MethodBackend>& methods) {
    for (const KnobRequest& r : requests) {
        bool read = false;
        for (const MethodBackend& mb : methods)
            read = read || mapKnob(methodInfo(mb.method).shadowMap, r.name);
        if (!read) {
            std::string list;
            for (const MethodBackend& mb : methods)
                for (const MethodKnob& k : methodInfo(mb.method).knobs)
                    list += (list.empty() ? "" : ", ") + methodInfo(mb.method).name + ": " + k.name;
            throw UsageError("--knob '" + r.item + "' names no knob of the methods given (theirs: " + list +
                             ")");
        }
    }
}

/// The search of one method: with the worst-scene objective each training scene's own best
/// first, then the joint search, then the defaults and the best point on the held-out scenes.
void tuneMethod(MethodResult& r, const std::vector<TuneScene>& training,
                const std::vector<TuneScene>& heldOut, RenderOptions o, const TuneArgs& args, bool worst) {
    if (worst) {
        // Each scene's own best first: the joint search's unit per scene.
        for (const TuneScene& scene : training) {
            MethodResult alone = r;
            if (!args.quiet)
                std::fprintf(stderr, "tune %s: %s alone\n", toString(r.mb).c_str(),
                             printable(scene.spec).c_str());
            Search(alone, std::vector<TuneScene>{scene}, o, args.budget, args.quiet).run();
            r.ownBests.push_back(alone.best.errors[0]);
            r.ownRenders += alone.renders;
            r.warnings.insert(alone.warnings.begin(), alone.warnings.end());
        }
    }
    Search(r, training, o, args.budget, args.quiet).run();
    // The held-out scenes, at the defaults and at the best point.
    const bool same = r.best.values == r.defaults.values;
    for (const TuneScene& s : heldOut) {
        o.params = r.paramsAt(r.defaults.values);
        const Frame d = renderFrame(s.scene, o);
        r.heldOutDefault.push_back(tuneError(d, s));
        ++r.heldOutRenders;
        if (same) {
            r.heldOutBest.push_back(r.heldOutDefault.back());
            continue;
        }
        o.params = r.paramsAt(r.best.values);
        const Frame b = renderFrame(s.scene, o);
        r.heldOutBest.push_back(tuneError(b, s));
        ++r.heldOutRenders;
    }
}

/// --json: each method's best knobs beside its defaults, per training and held-out scene.
nlohmann::json tuneJson(const TuneArgs& args, const std::vector<MethodResult>& results,
                        const std::vector<TuneScene>& training, const std::vector<TuneScene>& heldOut,
                        const RenderOptions& base, const MethodBackend& against, const SceneOptions& sets,
                        bool worst, double seconds) {
    nlohmann::json list = nlohmann::json::array();
    for (const MethodResult& r : results) {
        nlohmann::json searched = nlohmann::json::array();
        for (const SearchedKnob& k : r.knobs)
            searched.push_back({{"name", k.name},
                                {"lo", k.range.lo},
                                {"hi", k.range.hi},
                                {"scale", toString(k.range.scale)},
                                {"integer", k.integer}});
        auto perScene = [](const std::vector<TuneScene>& scenes, const std::vector<double>& d,
                           const std::vector<double>& b, const std::vector<double>& own) {
            nlohmann::json j = nlohmann::json::array();
            for (std::size_t i = 0; i < scenes.size(); ++i) {
                j.push_back({{"scene", scenes[i].spec},
                             {"default", d[i]},
                             {"best", b[i]},
                             {"facing_pixels", scenes[i].facing ? scenes[i].facing->facing : 0}});
                if (i < own.size()) j.back()["own_best"] = own[i];
            }
            return j;
        };
        list.push_back({{"method", toString(r.mb.method)},
                        {"backend", toString(r.mb.backend)},
                        {"knobs", knobsJson(r.mb.method, r.knobs, r.best.values, r.fixed, r.given)},
                        {"defaults", knobsJson(r.mb.method, r.knobs, r.defaults.values, r.fixed, r.given)},
                        {"searched", searched},
                        {"improved", r.best.objective < r.defaults.objective},
                        {"objective", {{"defaults", r.defaults.objective}, {"best", r.best.objective}}},
                        {"training", perScene(training, r.defaults.errors, r.best.errors, r.ownBests)},
                        {"validation", perScene(heldOut, r.heldOutDefault, r.heldOutBest, {})},
                        {"renders", r.renders},
                        {"own_renders", r.ownRenders},
                        {"evaluations", r.evaluations},
                        {"budget", args.budget},
                        {"budget_spent", r.budgetSpent},
                        {"held_out_renders", r.heldOutRenders},
                        {"seconds", r.seconds}});
    }
    return {{"version", version()},
            {"command", shellCommandLine(args.argv)},
            {"error", ERROR_NAME},
            {"objective", objectiveName(worst)},
            {"against", toString(against)},
            {"converged_frames", args.converged},
            {"set", sets.set},
            {"options",
             [&] {
                 nlohmann::json o = toJson(frameOptions(base));
                 for (const char* key : {"method", "backend", "params", "validation"}) o.erase(key);
                 return o;
             }()},
            {"seconds", seconds},
            {"machine", machineJson(base.backend == Backend::Vulkan, base.device)},
            {"methods", list}};
}

} // namespace

int runTune(TuneArgs& args) {
    Timer total;
    if (args.quiet) Progress::setEnabled(false);
    if (args.budget < 1 || args.budget > MAX_TUNE_BUDGET)
        throw UsageError("--budget " + std::to_string(args.budget) + " is out of range (1 to " +
                         std::to_string(MAX_TUNE_BUDGET) + ")");
    if (args.converged < 1 || args.converged > MAX_CONVERGED_FRAMES)
        throw UsageError("--converged " + std::to_string(args.converged) + " is out of range (1 to " +
                         std::to_string(MAX_CONVERGED_FRAMES) + ")");
    const RenderOptions base = resolveFrameOptions(args);
    const Backend backend = parseBackend(args.backend);
    const MethodBackend against = parseMethodBackend(args.against, Backend::Cpu);

    const std::vector<MethodBackend> methods = tunedMethods(args.methods, backend);
    std::vector<Method> all{against.method};
    for (const MethodBackend& mb : methods) all.push_back(mb.method);
    const std::vector<MethodParams> params = paramsForMethods(all, args.params);
    const std::set<std::string> given = paramNames(args.params);
    const std::vector<KnobRequest> requests = parseKnobRequests(args.knobs);
    checkKnobRequests(requests, methods);
    std::vector<MethodResult> results;
    for (std::size_t i = 0; i < methods.size(); ++i) {
        MethodResult r;
        r.mb = methods[i];
        r.fixed = params[i + 1];
        for (const std::string& name : given)
            if (r.fixed.count(name)) r.given.insert(name);
        r.knobs = searchedKnobs(methodInfo(r.mb.method), r.fixed, requests, given);
        results.push_back(std::move(r));
    }

    const std::vector<std::string> trainingSpecs = sceneList(args.scenes, "--scenes");
    const std::vector<std::string> heldOutSpecs = sceneList(args.validate, "--validate");
    if (trainingSpecs.empty()) throw UsageError("tune needs training scenes: --scenes SCENE…");
    for (const std::string& spec : heldOutSpecs)
        if (std::find(trainingSpecs.begin(), trainingSpecs.end(), spec) != trainingSpecs.end())
            throw UsageError("--validate " + spec +
                             " is a training scene too (--scenes): held-out scenes are "
                             "scenes the search did not see");
    const bool worst = args.objective == "worst";
    if (worst && trainingSpecs.size() < 2)
        throw UsageError("--objective worst weighs scenes against their own bests: give two or more "
                         "training scenes (with one, --objective mean finds the same knobs)");
    if (args.budget < int(trainingSpecs.size()))
        throw UsageError("--budget " + std::to_string(args.budget) +
                         " is less than one render per training scene (" +
                         std::to_string(trainingSpecs.size()) + ")");
    std::vector<InputFile> inputs;
    for (const std::string& spec : trainingSpecs)
        if (std::error_code ec; std::filesystem::is_regular_file(spec, ec))
            inputs.push_back({"a scene", spec});
    const std::vector<OutputFile> outputs = {{"--json", args.json, {".json"}}};
    checkOutputFiles(outputs, inputs);

    RenderOptions againstOptions = base;
    againstOptions.method = against.method;
    againstOptions.backend = against.backend;
    if (againstOptions.buffer == BufferKind::Transmittance &&
        !methodInfo(against.method).writesTransmittance())
        againstOptions.buffer = BufferKind::Bitmask;
    againstOptions.params = params[0];
    const SceneOptions sets = sceneOptionsOf(args);
    const bool useCache = !args.noCache;
    if (useCache && convergedCacheDirectory().empty() && !args.quiet)
        std::fprintf(stderr,
                     "note: no cache directory (set STSV_CACHE_DIR, XDG_CACHE_HOME or HOME): the converged "
                     "references are not cached\n");
    std::vector<TuneScene> training, heldOut;
    for (const std::string& spec : trainingSpecs)
        training.push_back(loadTuneScene(spec, sets, againstOptions, args.converged, useCache, args.quiet));
    for (const std::string& spec : heldOutSpecs)
        heldOut.push_back(loadTuneScene(spec, sets, againstOptions, args.converged, useCache, args.quiet));
    for (const std::vector<TuneScene>* list : {&training, &heldOut})
        for (const TuneScene& s : *list) {
            const std::vector<InputFile> read = sceneInputFiles(s.spec, s.scene);
            inputs.insert(inputs.end(), read.begin(), read.end());
        }
    checkOutputFiles(outputs, inputs);

    std::string trainingNames, heldOutNames;
    for (const TuneScene& s : training) trainingNames += (trainingNames.empty() ? "" : ", ") + s.spec;
    for (const TuneScene& s : heldOut) heldOutNames += (heldOutNames.empty() ? "" : ", ") + s.spec;
    std::printf(
        "tune on %s (training)%s: %dx%d, %d samples (%s, seed %u); error: %s (%s, %d x %d samples per "
        "pixel); objective: %s\n",
        printable(trainingNames).c_str(),
        heldOut.empty() ? "" : (", " + printable(heldOutNames) + " (held out)").c_str(), base.width,
        base.height, base.samples, toString(base.pattern).c_str(), base.seed, ERROR_NAME,
        toString(against).c_str(), args.converged, base.samples, objectiveName(worst));

    // The search's lines say where it is; a frame's own bar (peel's march) would interleave with them.
    Progress::setEnabled(false);
    for (MethodResult& r : results) {
        Timer timer;
        RenderOptions o = base;
        o.method = r.mb.method;
        o.backend = r.mb.backend;
        if (o.buffer == BufferKind::Transmittance && !methodInfo(r.mb.method).writesTransmittance())
            o.buffer = BufferKind::Bitmask;
        tuneMethod(r, training, heldOut, o, args, worst);
        r.seconds = timer.milliseconds() / 1000.0;
        for (const std::string& w : r.warnings)
            std::fprintf(stderr, "stsv: warning: %s\n", printable(w).c_str());
        printResult(r, training, heldOut, args.budget);
    }

    if (!args.json.empty()) {
        writeJson(args.json, tuneJson(args, results, training, heldOut, base, against, sets, worst,
                                      total.milliseconds() / 1000.0));
        reportWritten(args.json, args.quiet);
    }
    return 0;
}

KnobsFile readKnobsFile(const std::string& path) {
    const std::string text = readFileBytes(path, "knobs file", std::size_t(1) << 24);
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        const std::string what = e.what();
        const std::size_t tag = what.rfind("[json.exception", 0) == 0 ? what.find("] ") : std::string::npos;
        throw InputError(path, "not valid JSON: " + (tag == std::string::npos ? what : what.substr(tag + 2)));
    }
    KnobsFile file;
    file.path = path;
    nlohmann::json entries;
    if (j.is_object() && j.contains("methods"))
        entries = j["methods"];
    else if (j.is_object() && j.contains("method"))
        entries = nlohmann::json::array({j});
    else
        throw InputError(path,
                         "a knobs file is an object with \"methods\": [{\"method\": NAME, \"knobs\": {...}}, "
                         "...] (as tune --json writes it), or one {\"method\": NAME, \"knobs\": {...}}");
    if (!entries.is_array() || entries.empty())
        throw InputError(path,
                         "\"methods\" must be a non-empty array of {\"method\": NAME, \"knobs\": {...}}");
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const nlohmann::json& e = entries[i];
        const std::string where = "methods[" + std::to_string(i) + "]";
        if (!e.is_object() || !e.contains("method") || !e["method"].is_string() || !e.contains("knobs") ||
            !e["knobs"].is_object())
            throw InputError(path,
                             where + " must be an object with \"method\" (a name) and \"knobs\" (an object)");
        const std::string name = e["method"].get<std::string>();
        const MethodInfo* method = nullptr;
        for (const MethodInfo& m : methodTable())
            if (m.name == name) method = &m;
        if (!method)
            throw InputError(path,
                             where + ": unknown method '" + name + "' (one of " + methodNameList() + ")");
        if (file.find(method->id)) throw InputError(path, where + ": method " + name + " is listed twice");
        MethodParams knobs;
        for (const auto& [knob, value] : e["knobs"].items()) {
            const MethodKnob* k = method->knob(knob);
            if (!k) {
                if (const char* why = retiredShadowMapKnob(knob)) throw InputError(path, where + ": " + why);
                std::string list;
                for (const MethodKnob& mk : method->knobs) list += (list.empty() ? "" : ", ") + mk.name;
                throw InputError(path, where + ": " + name + " has no knob '" + knob +
                                           "' (its knobs: " + (list.empty() ? "none" : list) + ")");
            }
            if (!value.is_number())
                throw InputError(path, where + ": knob " + knob + " must be a number, not " + value.dump());
            const double v = value.get<double>();
            if (!(v >= k->min && v <= k->max) || (k->integer && std::floor(v) != v))
                throw InputError(path, where + ": " + knob + "=" + value.dump() + " is outside " + name +
                                           "'s range [" + formatNumber(k->min) + ", " + formatNumber(k->max) +
                                           "]" + (k->integer ? " of whole numbers" : ""));
            knobs[knob] = v;
        }
        file.methods.emplace_back(method->id, knobs);
    }
    return file;
}

std::vector<std::string> applyKnobsFile(const KnobsFile& file, const std::vector<Method>& methods,
                                        std::vector<MethodParams>& params,
                                        const std::vector<std::string>& paramItems) {
    const std::set<std::string> given = paramNames(paramItems);
    std::vector<std::string> labels(methods.size());
    for (std::size_t i = 0; i < methods.size(); ++i) {
        const MethodParams* knobs = file.find(methods[i]);
        if (!knobs) continue;
        for (const auto& [name, value] : *knobs) {
            const bool overridden = given.count(name) > 0;
            if (!overridden) params[i][name] = value;
            labels[i] += (labels[i].empty() ? "" : " ") + name + "=" + formatNumber(params[i].at(name)) +
                         (overridden ? " (--param; the file has " + formatNumber(value) + ")" : "");
        }
        if (labels[i].empty()) labels[i] = "none (the defaults)";
    }
    return labels;
}

} // namespace stsv
