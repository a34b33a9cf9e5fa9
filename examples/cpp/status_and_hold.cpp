// Status and hold over TCP with the C++ API (mcm/mcm.hpp): connect, `info`, the detailed
// status, `hold`, and the arm's state in HOLD.
//
// Against the simulated arm (`cargo run --release` in another terminal, JSON port 18010):
//
//   cmake -S capi -B build/capi && cmake --build build/capi && cmake --install build/capi --prefix ~/.local
//   cmake -S examples/cpp -B build/examples -DCMAKE_PREFIX_PATH=~/.local && cmake --build build/examples
//   build/examples/status_and_hold [--addr HOST:PORT]
#include <mcm/mcm.hpp>

#include <cstdio>
#include <cstring>
#include <string>

int main(int argc, char** argv) {
    std::string addr = "127.0.0.1:18010";
    for (int i = 1; i + 1 < argc; i += 2) {
        if (std::strcmp(argv[i], "--addr") == 0) addr = argv[i + 1];
    }
    try {
        mcm::TcpClient mcm = mcm::TcpClient::connect(addr).value();
        const mcm::Info info = mcm.info().value();
        std::printf("connected to %s (MCM %s, cycle %.3f s, %s)\n", info.robot, info.version,
                    info.cycle_time, info.simulated ? "simulated" : "real");
        const mcm::Status before = mcm.status_detail().value();
        std::printf("mode %s, all calibrated: %s, emergency stop: %s, cycle %llu\n",
                    mcm_mode_name(before.mode), before.all_calibrated ? "yes" : "no",
                    before.emergency_stop ? "pressed" : "released",
                    static_cast<unsigned long long>(before.cycle));
        const mcm::Status held = mcm.hold().value();
        std::printf("hold: mode %s, positions [", mcm_mode_name(held.mode));
        for (int i = 0; i < MCM_NUM_AXES; ++i) std::printf(i ? ", %.3f" : "%.3f", held.position[i]);
        std::printf("] deg\n");
        // An error as a value: axis 9 does not exist; the MCM's words come back unchanged.
        const mcm::Result<void> bad = mcm.move_axis(9, 0.0, 0.5);
        if (!bad) std::printf("move_axis 9: %s: %s\n", bad.error().name(), bad.error().message().c_str());
    } catch (const mcm::Exception& e) {
        std::fprintf(stderr, "error: %s: %s\n", e.error().name(), e.what());
        return 1;
    }
    return 0;
}
