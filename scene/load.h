// The one entry point the CLI uses: a scene from a built-in name, a .json scene or a bare mesh.
#pragma once

#include "scene/scene.h"

#include <iosfwd>
#include <map>
#include <string>
#include <vector>

namespace stsv {

/// Scene knobs and overrides from the command line, as given.
struct SceneOptions {
    std::map<std::string, std::string> set;  ///< `--set key=value`
    std::string camera = {};                 ///< `--camera JSON`: replaces the scene's camera
    std::vector<std::string> lights = {};    ///< `--light JSON` (each): replace the scene's lights
    std::vector<std::string> addLights = {}; ///< `--add-light JSON` (each): added to its lights
};

/// One knob a built-in scene accepts (for `stsv info` and error messages), declared once with its
/// default and the range `--set` accepts: a range whose ends each render a sensible image with
/// the scene's other knobs at their defaults (tests/scene/load_test.cpp renders both ends).
struct SceneKnob {
    enum class Kind { Real, Integer, Seed }; ///< Seed: any unsigned 64-bit integer (no range)
    std::string name;
    std::string defaultValue;
    std::string description; ///< what it sets, its unit and the accepted range
    Kind kind = Kind::Real;
    double lo = 0.0; ///< smallest accepted value (Real, Integer)
    double hi = 0.0; ///< largest accepted value (Real, Integer)
};

/// Prints "name=default" (the form `--set` takes).
std::ostream& operator<<(std::ostream& out, const SceneKnob& knob);

/// `spec` is a built-in name (see builtinSceneNames()), a `.json` scene file, or a bare `.obj` /
/// `.off` mesh (placed on a ground plane under a default light, with a camera that frames it).
/// Unknown names, unknown extensions and unknown or malformed knobs throw UsageError; bad files
/// throw InputError naming the file (and line). Then the options' camera and lights, in the JSON
/// scene format's objects, replace or join the scene's. The returned scene has passed
/// Scene::validate().
Scene loadScene(const std::string& spec, const SceneOptions& options = {});

/// "fence", "foliage".
std::vector<std::string> builtinSceneNames();

/// The knobs of a built-in scene, in a stable order; UsageError for an unknown name.
std::vector<SceneKnob> builtinSceneKnobs(const std::string& name);

/// One-line description of a built-in scene; UsageError for an unknown name.
std::string describeBuiltinScene(const std::string& name);

} // namespace stsv
