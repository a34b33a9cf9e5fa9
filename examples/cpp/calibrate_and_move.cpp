// Calibrate and move over TCP with the C++ API (mcm/mcm.hpp): `hold`, `calibrate` when an
// axis is not calibrated yet, `pvt`, `move_axis`, and a bounded wait for the arrival.
//
// Against the simulated arm (`cargo run --release` in another terminal, JSON port 18010),
// built as status_and_hold.cpp says:
//
//   build/examples/calibrate_and_move [--addr HOST:PORT] [--axis 1] [--target 20]
#include <mcm/mcm.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

int main(int argc, char** argv) {
    std::string addr = "127.0.0.1:18010";
    unsigned axis = 1;
    double target = 20.0;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (std::strcmp(argv[i], "--addr") == 0) addr = argv[i + 1];
        if (std::strcmp(argv[i], "--axis") == 0) axis = unsigned(std::atoi(argv[i + 1]));
        if (std::strcmp(argv[i], "--target") == 0) target = std::atof(argv[i + 1]);
    }
    // Errors as values here (no exceptions): each step says what failed and ends.
    auto r = mcm::TcpClient::connect(addr);
    if (!r) {
        std::fprintf(stderr, "error: %s\n", r.error().message().c_str());
        return 1;
    }
    mcm::TcpClient mcm = std::move(r).value();
    auto fail = [](const mcm::Error& e) {
        std::fprintf(stderr, "error: %s (%s, reject code %s)\n", e.message().c_str(), e.name(),
                     e.reject_name());
        return 1;
    };
    const auto t0 = std::chrono::steady_clock::now();
    const mcm::Result<bool> calibrated = mcm.calibrate_if_needed();
    if (!calibrated) return fail(calibrated.error());
    if (*calibrated) {
        const std::chrono::duration<double> took = std::chrono::steady_clock::now() - t0;
        std::printf("calibrated in %.1f s\n", took.count());
    } else {
        std::printf("already calibrated\n");
    }
    if (auto p = mcm.pvt(0.01); !p) return fail(p.error());
    if (auto m = mcm.move_axis(axis, target, 0.5); !m) return fail(m.error());
    std::printf("moving axis %u to %.3f deg\n", axis, target);
    const unsigned i = axis - 1;
    const auto s = mcm.wait_until("arrived", 20.0, [&](const mcm::Status& s) {
        return std::fabs(s.position[i] - target) < 0.01 && std::fabs(s.velocity[i]) < 1e-6;
    });
    if (!s) return fail(s.error());
    std::printf("axis %u at %.3f deg (mode %s)\n", axis, s->position[i], mcm_mode_name(s->mode));
    return 0;
}
