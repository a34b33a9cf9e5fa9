// A torque loop over shared memory at the cycle rate with the C++ API's control(callback):
// the MCM compensates gravity (and 70 % of the friction), the callback adds a virtual spring
// and damper on one axis, pulling it `--offset` degrees from where it starts.
//
// Run it on the robot's computer, against `cargo run --release` (instance "default"), built as
// status_and_hold.cpp says:
//
//   build/examples/torque_spring_shm [--instance NAME] [--axis 1] [--offset 5] [--seconds 3]
//   build/examples/torque_spring_shm --offset 0 --cycles 10000 --report   # the benchmark
//
// At the end it prints the loop's summary: cycles, cycles missed, and the share of answers to
// the state of cycle k that the core applied in cycle k + 1; with --report also PASS or FAIL
// against the target of at least 99.9 % (exit code 1 on FAIL).
#include <mcm/mcm.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {
constexpr double K = 150.0;  // spring [Nm/rad]
constexpr double D = 25.0;   // damper [Nm s/rad]
constexpr double RAD = M_PI / 180.0;
}  // namespace

int main(int argc, char** argv) {
    std::string instance = "default";
    unsigned axis = 1;
    double offset = 5.0, seconds = 3.0;
    long long cycles_arg = -1;
    bool report = false;
    for (int i = 1; i < argc; ++i) {
        const bool has = i + 1 < argc;
        if (std::strcmp(argv[i], "--report") == 0) report = true;
        else if (has && std::strcmp(argv[i], "--instance") == 0) instance = argv[++i];
        else if (has && std::strcmp(argv[i], "--axis") == 0) axis = unsigned(std::atoi(argv[++i]));
        else if (has && std::strcmp(argv[i], "--offset") == 0) offset = std::atof(argv[++i]);
        else if (has && std::strcmp(argv[i], "--seconds") == 0) seconds = std::atof(argv[++i]);
        else if (has && std::strcmp(argv[i], "--cycles") == 0) cycles_arg = std::atoll(argv[++i]);
    }
    if (axis < 1 || axis > MCM_NUM_AXES) {
        std::fprintf(stderr, "error: --axis %u is not allowed; expected 1 to 6\n", axis);
        return 2;
    }
    try {
        mcm::ShmClient mcm = mcm::ShmClient::connect(instance).value();
        if (mcm.calibrate_if_needed().value()) std::printf("calibrated first\n");
        mcm::ControlOptions o = mcm_control_options_default();
        o.timeout_s = 0.1;  // HOLD if this loop stops answering for 0.1 s
        mcm.torque_control(o).value();
        const mcm::State first = mcm.wait_state().value();
        const unsigned i = axis - 1;
        const double start = first.measured_position[i];
        const double set_point = start + offset;
        const double period_s = double(first.timing.period_ns) * 1e-9;
        const unsigned long long cycles =
            cycles_arg > 0 ? static_cast<unsigned long long>(cycles_arg)
                           : static_cast<unsigned long long>(std::llround(seconds / period_s));
        std::printf("axis %u: start %.3f deg, spring set-point %.3f deg, %llu cycles of %.1f ms\n",
                    axis, start, set_point, cycles, period_s * 1e3);
        double last = start;
        // The callback runs once per cycle: no allocation, no blocking.
        const mcm::ControlResult r = mcm.control([&](const mcm::State& s, mcm::Output& out) {
            if (s.seq >= first.seq + cycles) return mcm::Control::Finish;
            const double q = s.measured_position[i], v = s.velocity[i];
            last = q;
            out.values[i] = K * (set_point - q) * RAD - D * v * RAD;
            return mcm::Control::Continue;
        });
        mcm.hold().value();
        const mcm::State now = mcm.latest().value();
        std::printf("axis %u ended at %.3f deg (%.3f deg from the set-point), now %s\n", axis, last,
                    last - set_point, mcm_mode_name(now.mode));
        const mcm::ControlSummary& sum = r.summary;
        std::printf(
            "control loop: %llu cycles, %llu missed, %llu commands sent, applied in the next cycle "
            "%llu/%llu (%.2f %%), %llu unanswered\n",
            static_cast<unsigned long long>(sum.cycles), static_cast<unsigned long long>(sum.missed),
            static_cast<unsigned long long>(sum.sent), static_cast<unsigned long long>(sum.on_time),
            static_cast<unsigned long long>(sum.on_time + sum.late), r.on_time_percent(),
            static_cast<unsigned long long>(sum.unanswered));
        r.end.value();  // the loop ended by Finish, else throws why
        if (report) {
            const bool pass = r.on_time_percent() >= 99.9;
            std::printf("%s: %.3f %% of answers applied in cycle k+1 (target >= 99.9 %%)\n",
                        pass ? "PASS" : "FAIL", r.on_time_percent());
            return pass ? 0 : 1;
        }
    } catch (const mcm::Exception& e) {
        std::fprintf(stderr, "error: %s: %s\n", e.error().name(), e.what());
        return 1;
    }
    return 0;
}
