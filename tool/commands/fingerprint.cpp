// fingerprint: a backend's rules inferred from the probe scenes (harness/fingerprint.hpp),
// printed with their evidence; the profile written (-o) and, with --json, every finding.
#include "harness/fingerprint.hpp"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <new>

#include "commands/commands.hpp"
#include "harness/encode.hpp"
#include "harness/profile_io.hpp"

namespace tool {
namespace {

struct FingerprintArgs {
    BackendArgs against{"osmesa"};
    std::string output;
    std::string json;
};

int run_fingerprint(const FingerprintArgs& a) {
    auto backend = backend_or_report(a.against, "fingerprint");
    if (!backend) return kExitBackendFailure;
    harness::FingerprintResult r;
    try {
        // A fresh worker of the same implementation, for the probes that depend on history.
        r = harness::fingerprint(
            *backend, [](const std::string& s) { std::cerr << "fingerprint: " << s << "\n"; },
            [&a]() -> std::unique_ptr<harness::Backend> {
                return backend_or_report(a.against, "fingerprint");
            });
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const std::exception& e) {
        std::cerr << "fingerprint: " << harness::encode::terminal(e.what()) << "\n";
        return kExitBackendFailure;
    }
    std::cout << harness::fingerprint_text(r);
    const auto write = [](const std::string& path, const std::string& text) {
        const std::string tmp = path + ".tmp";
        {
            std::ofstream o(tmp, std::ios::binary);
            o << text << "\n";
            if (!o) {
                std::cerr << harness::encode::terminal(path) << ": cannot write\n";
                std::error_code ec;
                std::filesystem::remove(tmp, ec);
                return false;
            }
        }
        std::filesystem::rename(tmp, path);
        return true;
    };
    if (!write(a.output, harness::profile_to_json(r.profile))) return kExitBadInput;
    if (!a.json.empty() && !write(a.json, harness::fingerprint_json(r))) return kExitBadInput;
    std::cerr << harness::encode::terminal(a.output) << ": profile " << r.profile.name << "\n";
    // Undecided rules are a finding, not a failure of the tool: the profile is written, and the
    // exit code says that it is incomplete.
    return r.complete() ? kExitOk : kExitMismatch;
}

}  // namespace

Command add_fingerprint_command(CLI::App& app) {
    auto a = std::make_shared<FingerprintArgs>();
    auto* cmd = app.add_subcommand(
        "fingerprint",
        "Infer a backend's rules from probe scenes and write a profile the reference loads");
    add_backend_option(cmd, "--against", a->against.backend,
                       "Backend to fingerprint (ref: the reference under --profile)",
                       {"ref", "osmesa", "egl"});
    add_driver_options(cmd, a->against);
    add_profile_options(cmd, a->against.profile);
    cmd->add_option("-o,--output", a->output, "The inferred profile (JSON)")->required();
    cmd->add_option("--json", a->json, "Every finding with its evidence (JSON)");
    return {cmd, [a] { return run_fingerprint(*a); }};
}

}  // namespace tool
