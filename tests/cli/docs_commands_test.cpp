// Every `stsv …` command the README and docs/ show runs: each is taken from the Markdown (code
// blocks, with `\` continuations, and inline code spans), made small (a 16×12 frame, 16 samples,
// one timed frame, a converged reference of 2, a tune budget of 8 renders) and run in a scratch
// folder, and must exit 0. A renamed option, a removed preset or a wrong example fails here.
// Synopses with placeholders (SCENE, [options], a|b) are not commands and are skipped.
#include "cli_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace stsv::test {
namespace {

namespace fs = std::filesystem;

struct DocCommand {
    std::string file;
    std::size_t line = 0;
    std::string text;
};

std::vector<std::string> docFiles() {
    const fs::path root(STSV_SOURCE_DIR);
    std::vector<std::string> files{(root / "README.md").string()};
    for (const fs::directory_entry& e : fs::directory_iterator(root / "docs"))
        if (e.path().extension() == ".md") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    return files;
}

/// The `stsv …` commands of one Markdown file: lines of code blocks (a leading `$ ` dropped,
/// continuations joined; a synopsis with a description column, after three spaces, left out) and
/// inline code spans that start with "stsv ".
std::vector<DocCommand> commandsIn(const std::string& path) {
    std::ifstream in(path);
    std::vector<DocCommand> commands;
    std::string line;
    std::size_t number = 0;
    bool inBlock = false;
    DocCommand pending;
    static const std::regex span("`(stsv [^`]+)`");
    while (std::getline(in, line)) {
        ++number;
        if (line.rfind("```", 0) == 0) {
            inBlock = !inBlock;
            continue;
        }
        if (inBlock) {
            std::string text = line;
            if (!pending.text.empty()) {
                pending.text += " " + text;
            } else {
                if (text.rfind("$ ", 0) == 0) text.erase(0, 2);
                if (text.rfind("stsv ", 0) != 0 && text != "stsv") continue;
                pending = {path, number, text};
            }
            if (!pending.text.empty() && pending.text.back() == '\\') {
                pending.text.pop_back();
                continue;
            }
            // A synopsis table ("stsv info      what it prints") is no command.
            if (pending.text.find("   ") == std::string::npos) commands.push_back(pending);
            pending = {};
            continue;
        }
        for (std::sregex_iterator it(line.begin(), line.end(), span), end; it != end; ++it)
            commands.push_back({path, number, (*it)[1].str()});
    }
    return commands;
}

/// "hull,mesh" → {"hull", "mesh"}.
std::vector<std::string> splitCommas(const std::string& list) {
    std::vector<std::string> out;
    std::stringstream in(list);
    for (std::string item; std::getline(in, item, ',');) out.push_back(item);
    return out;
}

/// Shell-like words: spaces separate, single and double quotes group.
std::vector<std::string> words(const std::string& text) {
    std::vector<std::string> out;
    std::string word;
    bool any = false;
    char quote = 0;
    for (char c : text) {
        if (quote) {
            if (c == quote)
                quote = 0;
            else
                word += c;
        } else if (c == '\'' || c == '"') {
            quote = c;
            any = true;
        } else if (c == ' ') {
            if (any || !word.empty()) out.push_back(word);
            word.clear();
            any = false;
        } else {
            word += c;
        }
    }
    if (any || !word.empty()) out.push_back(word);
    return out;
}

/// A synopsis, not a command: placeholders in capitals, alternatives, optional parts.
bool isSynopsis(const std::vector<std::string>& args) {
    static const std::regex placeholder(
        "(^|[^a-z])(SCENE|NAME|DIR|FILE|WxH|A\\.npy|B\\.npy|M|B|N|K)([^a-z]|$)");
    for (const std::string& a : args) {
        if (a.find('[') != std::string::npos || a.find("…") != std::string::npos ||
            a.find("...") != std::string::npos)
            return true;
        if (a.find('|') != std::string::npos && a.front() != '{') return true;
        if (a.front() != '{' && std::regex_search(a, placeholder)) return true;
    }
    return false;
}

/// The command made small enough for the test suite, with paths of the checkout made absolute.
std::vector<std::string> smallVersion(std::vector<std::string> args) {
    const std::string command = args.size() > 1 ? args[1] : "";
    auto set = [&](const std::string& option, const std::string& value) {
        for (std::size_t i = 0; i + 1 < args.size(); ++i)
            if (args[i] == option) {
                args[i + 1] = value;
                return;
            }
        args.push_back(option);
        args.push_back(value);
    };
    const bool listing = std::find(args.begin(), args.end(), "--list-presets") != args.end();
    const bool npyPair =
        args.size() > 2 && args[2].size() > 4 && args[2].substr(args[2].size() - 4) == ".npy";
    const bool framed = command == "render" || command == "compare" || command == "bench" ||
                        command == "tune" || (command == "info" && args.size() > 2 && args[2].front() != '-');
    if (framed && !listing && !npyPair) {
        set("--size", "16x12");
        if (command != "info") set("--samples", "16");
    }
    if (command == "bench" && !listing) {
        set("--repeat", "1");
        set("--warmup", "0");
    }
    if (command == "tune") { // a few points of the search
        set("--budget", "8");
        set("--converged", "2");
    }
    for (std::size_t i = 0; i + 1 < args.size(); ++i)
        if (args[i] == "--converged") args[i + 1] = "2";
    // Inputs of the checkout become absolute; outputs stay in the scratch folder (their folders
    // made there), so that no example overwrites a file of the checkout.
    static const std::vector<std::string> outputOptions = {
        "-o",           "--output", "--visibility", "--dump-ls", "--stats",
        "--shadow-map", "--json",   "--out",        "--report",  "--sheet"};
    for (std::size_t i = 2; i < args.size(); ++i) {
        const bool output =
            std::find(outputOptions.begin(), outputOptions.end(), args[i - 1]) != outputOptions.end();
        if (output) {
            const fs::path parent = fs::path(args[i]).parent_path();
            if (!parent.empty() && parent.is_relative()) fs::create_directories(parent);
        } else if (args[i].find('/') != std::string::npos && args[i].front() != '-' &&
                   fs::exists(fs::path(STSV_SOURCE_DIR) / args[i])) {
            args[i] = (fs::path(STSV_SOURCE_DIR) / args[i]).string();
        }
    }
    args.erase(args.begin()); // "stsv"
    if (command != "info" && !listing) args.push_back("-q");
    return args;
}

TEST(DocsCommands, EveryStsvCommandInTheReadmeAndDocsRuns) {
    ScratchDir dir;
    const fs::path before = fs::current_path();
    fs::current_path(dir.path());
    // The real-meshes preset names its meshes relative to the checkout, where `make test-deps`
    // fetched them (bench/fetch_meshes.sh): the scratch folder links that folder.
    const fs::path meshes = fs::path(STSV_SOURCE_DIR) / "build" / "meshes";
    if (fs::is_directory(meshes)) {
        fs::create_directories("build");
        fs::create_directory_symlink(meshes, fs::path("build") / "meshes");
    }
    std::size_t ran = 0, refused = 0;
    for (const std::string& file : docFiles())
        for (const DocCommand& c : commandsIn(file)) {
            const std::vector<std::string> all = words(c.text);
            if (all.empty() || all[0] != "stsv" || isSynopsis(all)) continue;
            // A subcommand named in prose ("`stsv bench` times frames") is no example to run.
            if (all.size() == 2 && all[1] != "info") continue;
            const std::vector<std::string> args = smallVersion(all);
            const CliResult r = runStsv(args);
            std::string shown;
            for (const std::string& a : args) shown += " " + a;
            ++ran;
            // `--extrusion mesh` (or a bench's list with mesh in it) needs VK_EXT_mesh_shader: on a
            // driver without it (Debian 12's lavapipe) the command refuses and says so; the mesh
            // path itself runs in ctest's mesh_shaders.lavapipe_backports, on the second lavapipe.
            bool mesh = false;
            for (std::size_t i = 0; i + 1 < all.size(); ++i)
                if (all[i] == "--extrusion")
                    for (const std::string& stage : splitCommas(all[i + 1])) mesh = mesh || stage == "mesh";
            if (mesh && r.code != 0 &&
                r.err.find("lacks VK_EXT_mesh_shader (--extrusion mesh)") != std::string::npos) {
                ++refused;
                continue;
            }
            EXPECT_EQ(r.code, 0) << fs::path(c.file).filename().string() << ":" << c.line << ": " << c.text
                                 << "\n  ran: stsv" << shown << "\n  stderr: " << r.err;
        }
    fs::current_path(before);
    std::printf(
        "ran %zu commands from the README and docs/ (%zu refused --extrusion mesh: no mesh shaders)\n", ran,
        refused);
    EXPECT_GE(ran, 10u);
}

} // namespace
} // namespace stsv::test
