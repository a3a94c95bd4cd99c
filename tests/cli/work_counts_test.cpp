// The work behind the performance tables, held without timing anything: the machine-independent
// counts `stsv bench` reports (fragments, samples tested, cluster tests, tile entries, edges,
// silhouettes) of the scenes and methods the README's and docs/measurements.md's tables measure,
// rendered again at a small size and compared with tests/data/work_counts.json. The counts are
// deterministic on both backends (sums of per-thread counts, atomic counters on Vulkan), so a
// change that does more work — or less — fails here, with the count it changed. A change meant to
// alter the work regenerates the record and says why in its commit:
//   STSV_RECORD_WORK_COUNTS=tests/data/work_counts.json build/tests/test_cli --gtest_filter='WorkCounts.*'
#include "tests/cli/cli_test_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace stsv {
namespace {

using nlohmann::json;
using test::readJson;
using test::runStsv;
using test::ScratchDir;

/// The runs whose counts are held: each table's scene and methods on both backends, small.
struct WorkRun {
    const char* name;
    std::vector<std::string> args;
};

const std::vector<WorkRun>& workRuns() {
    static const std::vector<WorkRun> runs = {
        // bench-fence-1024, bench-fence-vs-mesh: STSV and DCS+STSV on the fence.
        {"fence", {"fence", "--methods", "stsv,dcs+stsv"}},
        // bench-knot-methods, bench-knot-scale: the knot's wedge methods and STSV.
        {"knot", {"knot", "--methods", "stsv,dcs,pw,dcs+stsv"}},
        // bench-foliage-count and -dense: STSV on foliage.
        {"foliage", {"foliage", "--methods", "stsv", "--set", "count=1000"}},
        // bench-particles: STSV and DCS+STSV among the particles.
        {"particles", {"particles", "--methods", "stsv,dcs+stsv", "--set", "count=1000"}},
    };
    return runs;
}

/// Whether a field of a pass's statistics is a count of work (an integer that names no time,
/// capacity or memory the driver chose).
bool isWorkCount(const std::string& key, const json& value) {
    if (!value.is_number_integer()) return false;
    for (const char* skip : {"_ms", "capacity", "bytes", "parts"})
        if (key.find(skip) != std::string::npos) return false;
    return true;
}

/// The counts of one bench --json file: "method/backend" → group → light → {count: value}.
json countsOf(const json& bench) {
    json out = json::object();
    for (const json& c : bench.at("configurations")) {
        const std::string key = c.at("method").get<std::string>() + "/" + c.at("backend").get<std::string>();
        for (const char* group : {"stsv", "wedges", "center"}) {
            if (!c.contains(group) || !c.at(group).is_array()) continue;
            json lights = json::array();
            for (const json& light : c.at(group)) {
                json counts = json::object();
                for (const auto& [name, value] : light.items())
                    if (isWorkCount(name, value)) counts[name] = value;
                lights.push_back(counts);
            }
            out[key][group] = lights;
        }
    }
    return out;
}

json benchCounts(const WorkRun& run, const ScratchDir& dir) {
    const std::string path = dir.file(std::string(run.name) + ".json");
    std::vector<std::string> args = {"bench"};
    args.insert(args.end(), run.args.begin(), run.args.end());
    args.insert(args.end(), {"--backends", "cpu,vulkan", "--size", "96x72", "--samples", "32", "--repeat",
                             "1", "--warmup", "0", "--json", path, "-q"});
    const test::CliResult r = runStsv(args);
    EXPECT_EQ(r.code, 0) << run.name << ": " << r.err;
    if (r.code != 0) return json::object();
    return countsOf(readJson(path));
}

std::string recordPath() {
    return std::string(STSV_SOURCE_DIR) + "/tests/data/work_counts.json";
}

TEST(WorkCounts, EveryCountIsAsRecorded) {
    // The CPU's G-buffer is traced by Embree, whose kernels round differently from one instruction
    // set to another (SSE, AVX2, AVX-512): a visible point a last bit apart tips a bound test or
    // two. Its SSE2 kernels, which every x86-64 CPU has, make the counts every machine's (as the
    // golden buffers'; tests/golden/README.md).
    const test::ScopedEnv sse2("STSV_EMBREE_CONFIG", "isa=sse2");
    ScratchDir dir;
    json now = json::object();
    for (const WorkRun& run : workRuns()) now[run.name] = benchCounts(run, dir);
    if (const char* record = std::getenv("STSV_RECORD_WORK_COUNTS")) {
        std::ofstream(record) << now.dump(1) << "\n";
        GTEST_SKIP() << "recorded " << record;
    }
    const json recorded = readJson(recordPath());
    std::size_t compared = 0;
    for (const WorkRun& run : workRuns()) {
        ASSERT_TRUE(recorded.contains(run.name)) << run.name << " is not in " << recordPath();
        const json& was = recorded.at(run.name);
        const json& is = now.at(run.name);
        EXPECT_EQ(is.size(), was.size()) << run.name << ": the configurations changed";
        for (const auto& [config, groups] : was.items())
            for (const auto& [group, lights] : groups.items())
                for (std::size_t l = 0; l < lights.size(); ++l)
                    for (const auto& [name, value] : lights[l].items()) {
                        const std::string where = std::string(run.name) + " " + config + " " + group +
                                                  " light " + std::to_string(l) + " " + name;
                        ASSERT_TRUE(is.contains(config) && is.at(config).contains(group) &&
                                    is.at(config).at(group).size() > l &&
                                    is.at(config).at(group)[l].contains(name))
                            << where << " is no longer reported";
                        const auto count = is.at(config).at(group)[l].at(name).get<long long>();
                        EXPECT_EQ(count, value.get<long long>())
                            << where << ": " << count << " now, " << value << " recorded ("
                            << (count > value.get<long long>() ? "more work" : "less work")
                            << "; if meant, re-record: see tests/cli/work_counts_test.cpp)";
                        ++compared;
                    }
    }
    // Not vacuous: every run reports its fragments and samples on both backends.
    EXPECT_GT(compared, 40u);
}

} // namespace
} // namespace stsv
