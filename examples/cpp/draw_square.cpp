// Draw a square in the air with `move_linear`, over TCP with the C++ API (mcm/mcm.hpp): the TCP
// on four straight sides in the horizontal plane through where it starts, its orientation
// kept; each corner checked on the TCP state the MCM reports once the arm is at rest there.
//
// Against the simulated arm (`cargo run --release` in another terminal, JSON port 18010),
// built as status_and_hold.cpp says:
//
//   build/examples/draw_square [--addr HOST:PORT] [--side 0.1] [--velocity 0.1]
#include <mcm/mcm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

// The joint angles [deg] the square starts from (its first corner): away from singularities.
constexpr mcm::Six kStart = {20.0, 30.0, 60.0, -40.0, 50.0, 10.0};

bool still(const mcm::Status& s) {
    return std::all_of(std::begin(s.velocity), std::end(s.velocity),
                       [](double v) { return std::fabs(v) < 1e-3; });
}

// The largest coordinate difference [m] between the reported TCP and `p`.
double tcp_error(const mcm::Status& s, const std::array<double, 3>& p) {
    if (!s.has_cartesian) return INFINITY;
    double e = 0.0;
    for (int k = 0; k < 3; ++k) e = std::max(e, std::fabs(s.cartesian.position[k] - p[k]));
    return e;
}

}  // namespace

int main(int argc, char** argv) {
    std::string addr = "127.0.0.1:18010";
    double side = 0.1;
    double velocity = 0.1;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (std::strcmp(argv[i], "--addr") == 0) addr = argv[i + 1];
        if (std::strcmp(argv[i], "--side") == 0) side = std::atof(argv[i + 1]);
        if (std::strcmp(argv[i], "--velocity") == 0) velocity = std::atof(argv[i + 1]);
    }
    try {
        mcm::TcpClient mcm = mcm::TcpClient::connect(addr).value();
        if (mcm.calibrate_if_needed().value()) std::printf("calibrated first\n");
        mcm.pvt(0.01).value();
        const mcm::MoveAllResult m = mcm.move_all(kStart, 0.5).value();
        const mcm::Status s = mcm.wait_until("at the start", m.max_time_to_target + 5.0,
                                             [](const mcm::Status& s) {
                                                 double d = 0.0;
                                                 for (int i = 0; i < 6; ++i)
                                                     d = std::max(d, std::fabs(s.position[i] - kStart[i]));
                                                 return d < 0.01 && still(s);
                                             })
                                  .value();
        if (!s.has_cartesian) {
            std::fprintf(stderr, "error: no cartesian_state: is every axis calibrated?\n");
            return 1;
        }
        const double x = s.cartesian.position[0], y = s.cartesian.position[1],
                     z = s.cartesian.position[2];
        std::printf("start corner [m]: %.4f %.4f %.4f\n", x, y, z);
        const std::array<std::array<double, 3>, 4> corners = {
            {{x + side, y, z}, {x + side, y + side, z}, {x, y + side, z}, {x, y, z}}};
        double worst = 0.0;
        for (size_t i = 0; i < corners.size(); ++i) {
            const auto& c = corners[i];
            mcm::MoveLinear line{};
            std::copy(c.begin(), c.end(), line.position);
            line.velocity = velocity;  // orientation kept, default acceleration
            const mcm::MoveLinearResult r = mcm.move_linear(line).value();
            const mcm::Status at = mcm.wait_until("at the corner", r.duration + 5.0,
                                                  [&](const mcm::Status& s) {
                                                      return tcp_error(s, c) < 1e-3 && still(s);
                                                  })
                                       .value();
            const double e = tcp_error(at, c);
            worst = std::max(worst, e);
            std::printf("side %zu: %.3f s, corner [%.4f, %.4f, %.4f], error %.6f m\n", i + 1,
                        r.duration, c[0], c[1], c[2], e);
        }
        std::printf("square of %.3f m drawn; largest corner error %.6f m\n", side, worst);
        mcm.hold().value();
    } catch (const mcm::Exception& e) {
        std::fprintf(stderr, "error: %s (%s)\n", e.what(), e.error().name());
        return 1;
    }
    return 0;
}
