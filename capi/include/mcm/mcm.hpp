// The C++17 API of the MCM client library: a header-only RAII layer over the C API (mcm.h).
//
// Errors: every call returns an mcm::Result<T> (primary; no exception is needed, it works
// with -fno-exceptions): test it (`if (!r)`, `r.ok()`), read `r.error()` (code, reject code,
// the MCM's message), or call `r.value()`, which throws mcm::Exception when it holds an error
// (and aborts with the message when exceptions are off). No exception crosses the C ABI: a
// callback's exception is caught in this header, the loop is ended and the exception rethrown
// after the C call returned.
//
// Threads: a TcpClient is used by one thread at a time; a ShmClient only on the thread that
// created it. Real-time safe after connect (no lock, no blocking; the reads allocate nothing,
// each command sent one small allocation inside iceoryx2 0.10's publisher): ShmClient::wait_state,
// latest, set_torques, set_velocities, client_id, missed_states and the running loop of
// control() (its Result<void> allocates only when the loop ends with an error).
//
// docs/clients.md ("C and C++") has the build with CMake, the install and the examples.
#ifndef MCM_MCM_HPP
#define MCM_MCM_HPP

#include "mcm/mcm.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace mcm {

using State = mcm_state_t;
using Status = mcm_status_t;
using TcpState = mcm_tcp_state_t;
using Info = mcm_info_t;
using ShmInfo = mcm_shm_info_t;
using MoveAllResult = mcm_move_all_result_t;
using Pose = mcm_pose_t;
using Tool = mcm_tool_t;
using Payload = mcm_payload_t;
using MoveLinear = mcm_move_linear_t;
using MoveLinearResult = mcm_move_linear_result_t;
using CalibrateOptions = mcm_calibrate_t;
using ControlOptions = mcm_control_options_t;
using PvtPoint = mcm_pvt_point_t;
using ControlSummary = mcm_control_summary_t;
using Output = mcm_control_output_t;
using Six = std::array<double, MCM_NUM_AXES>;
/// A Cartesian vector: x, y, z.
using Vec3 = std::array<double, 3>;
/// The frame whose axes a Cartesian velocity is given in.
enum class Frame : uint32_t { Base = 0, Tool = 1 };

/// Why a call did not succeed: the C API's code, the MCM's reject code (0: none) and the
/// message (the MCM's own words where it answered).
class Error {
public:
    Error(mcm_error_t code, uint32_t reject, std::string message)
        : code_(code), reject_(reject), message_(std::move(message)) {}
    mcm_error_t code() const noexcept { return code_; }
    /// The reject code (`mcm_reject_name` names it; e.g. 16 "busy"), 0 for none.
    uint32_t reject() const noexcept { return reject_; }
    const std::string& message() const noexcept { return message_; }
    /// "MCM_ERR_REFUSED", ...
    const char* name() const noexcept { return mcm_error_name(code_); }
    const char* reject_name() const noexcept { return mcm_reject_name(reject_); }

private:
    mcm_error_t code_;
    uint32_t reject_;
    std::string message_;
};

/// Thrown by Result::value() when the result holds an error.
class Exception : public std::runtime_error {
public:
    explicit Exception(Error e) : std::runtime_error(e.message()), error_(std::move(e)) {}
    const Error& error() const noexcept { return error_; }

private:
    Error error_;
};

namespace detail {
[[noreturn]] inline void fail(const Error& e) {
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
    throw Exception(e);
#else
    std::fprintf(stderr, "mcm: %s: %s\n", e.name(), e.message().c_str());
    std::abort();
#endif
}
}  // namespace detail

/// A value or the Error of the call (in the manner of C++23's std::expected).
template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : value_(std::move(value)) {}
    Result(Error error) : error_(std::move(error)) {}
    bool ok() const noexcept { return value_.has_value(); }
    explicit operator bool() const noexcept { return ok(); }
    /// The value; throws mcm::Exception (or aborts without exceptions) when it is an error.
    T& value() & {
        if (!ok()) detail::fail(*error_);
        return *value_;
    }
    T value() && {
        if (!ok()) detail::fail(*error_);
        return std::move(*value_);
    }
    const T& operator*() const { return *value_; }
    const T* operator->() const { return &*value_; }
    /// The error; only when !ok().
    const Error& error() const { return *error_; }

private:
    std::optional<T> value_;
    std::optional<Error> error_;
};

template <>
class [[nodiscard]] Result<void> {
public:
    Result() = default;
    Result(Error error) : error_(std::move(error)) {}
    bool ok() const noexcept { return !error_.has_value(); }
    explicit operator bool() const noexcept { return ok(); }
    /// Throws mcm::Exception (or aborts without exceptions) when it is an error.
    void value() const {
        if (!ok()) detail::fail(*error_);
    }
    const Error& error() const { return *error_; }

private:
    std::optional<Error> error_;
};

/// What the control loop's callable answers a state with.
enum class Control { Continue = MCM_CONTROL_CONTINUE, Finish = MCM_CONTROL_FINISH };

/// The end of a control loop: its summary always, and why it ended (ok: the callable returned
/// Control::Finish).
struct ControlResult {
    ControlSummary summary;
    Result<void> end;
    explicit operator bool() const noexcept { return end.ok(); }
    /// Share of the answered commands applied in the next cycle [%].
    double on_time_percent() const noexcept {
        const double answered = double(summary.on_time + summary.late);
        return answered == 0 ? 0.0 : 100.0 * double(summary.on_time) / answered;
    }
};

namespace detail {
inline Error thread_error(mcm_error_t code) {
    return Error(code, mcm_last_reject(), mcm_last_error());
}

template <class F, class S>
struct Predicate {
    explicit Predicate(F* fn) : f(fn) {}
    F* f;
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
    std::exception_ptr thrown;
#endif
    static int32_t call(const S* s, void* user) noexcept {
        auto* self = static_cast<Predicate*>(user);
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
        try {
            return (*self->f)(*s) ? 1 : 0;
        } catch (...) {
            self->thrown = std::current_exception();
            return 1;
        }
#else
        return (*self->f)(*s) ? 1 : 0;
#endif
    }
    void rethrow() {
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
        if (thrown) std::rethrow_exception(thrown);
#endif
    }
};
}  // namespace detail

namespace detail {
/// Closes a C handle (the destructor of the RAII classes).
struct Close {
    void operator()(mcm_tcp_client_t* h) const noexcept { mcm_tcp_close(h); }
    void operator()(mcm_shm_client_t* h) const noexcept { mcm_shm_close(h); }
};

/// Of the C functions of one command, `tcp` (mcm_tcp_<name>) or `shm` (mcm_shm_<name>): the
/// one of the handle H.
template <class H, class Tcp, class Shm>
constexpr auto pick(Tcp tcp, [[maybe_unused]] Shm shm) noexcept {
    if constexpr (std::is_same_v<H, mcm_tcp_client_t>) {
        return tcp;
    } else {
        static_assert(std::is_same_v<H, mcm_shm_client_t>, "a handle of mcm.h");
        return shm;
    }
}

// The C function `mcm_tcp_<name>` or `mcm_shm_<name>` of the handle type H. A macro of this
// header alone, with a name of its own (undefined again after the class): it pastes the
// function's name, which a template cannot.
#ifdef MCM_HPP_FN
#error "MCM_HPP_FN is mcm.hpp's own macro; do not define it"
#endif
#define MCM_HPP_FN(name) ::mcm::detail::pick<H>(&mcm_tcp_##name, &mcm_shm_##name)

/// The commands both transports have, once for both handles (TcpClient and ShmClient derive
/// from it). Where the transports answer differently, the type says it: a mode change answers
/// the state over TCP (Status) and nothing over shared memory; `info` answers Info over TCP
/// and ShmInfo over shared memory; `wait_until` watches a Status over TCP and a State over
/// shared memory.
template <class H>
class Client {
    static constexpr bool kTcp = std::is_same_v<H, mcm_tcp_client_t>;

public:
    /// What a mode change (hold, release, pvt, torque_control, velocity_control) answers.
    using ModeAnswer = std::conditional_t<kTcp, Status, void>;
    using InfoAnswer = std::conditional_t<kTcp, Info, ShmInfo>;
    /// What wait_until's predicate sees: the state over TCP is a Status (asked every 10 ms),
    /// over shared memory every cycle's State.
    using Observed = std::conditional_t<kTcp, Status, State>;

    Client(Client&&) noexcept = default;
    Client& operator=(Client&&) noexcept = default;

    /// The C handle, for functions this layer does not wrap.
    H* handle() noexcept { return h_.get(); }

    Result<InfoAnswer> info() {
        InfoAnswer i{};
        return with(MCM_HPP_FN(info)(h(), &i), i);
    }
    /// Enter HOLD (open to every client).
    Result<ModeAnswer> hold() {
        return mode([&](auto... status) { return MCM_HPP_FN(hold)(h(), status...); });
    }
    Result<ModeAnswer> release() {
        return mode([&](auto... status) { return MCM_HPP_FN(release)(h(), status...); });
    }
    Result<ModeAnswer> pvt(double dt_s) {
        return mode([&](auto... status) { return MCM_HPP_FN(pvt)(h(), dt_s, status...); });
    }
    /// Home the axes (default options: all axes, default directions); returns when done.
    Result<void> calibrate(const CalibrateOptions& o = CalibrateOptions{}) {
        return done(MCM_HPP_FN(calibrate)(h(), &o));
    }
    /// hold, then calibrate only when needed; true when it calibrated.
    Result<bool> calibrate_if_needed() {
        bool b = false;
        return with(MCM_HPP_FN(calibrate_if_needed)(h(), &b), b);
    }
    Result<ModeAnswer> torque_control(const ControlOptions& o = mcm_control_options_default()) {
        return mode([&](auto... status) { return MCM_HPP_FN(torque_control)(h(), &o, status...); });
    }
    /// Without waiting for the answer; a refusal comes as an event. Real-time safe over
    /// shared memory.
    Result<void> set_torques(const Six& t) { return done(MCM_HPP_FN(set_torques)(h(), t.data())); }
    Result<ModeAnswer> velocity_control(const ControlOptions& o = mcm_control_options_default()) {
        return mode(
            [&](auto... status) { return MCM_HPP_FN(velocity_control)(h(), &o, status...); });
    }
    /// Without waiting for the answer. Real-time safe over shared memory.
    Result<void> set_velocities(const Six& v) {
        return done(MCM_HPP_FN(set_velocities)(h(), v.data()));
    }
    /// The TCP's velocity in VELOCITY_CONTROL: linear [m/s], angular [deg/s], in the base
    /// frame's axes or the TCP's own. Without waiting for the answer. Real-time safe over
    /// shared memory.
    Result<void> set_cartesian_velocity(const Vec3& linear, const Vec3& angular,
                                        Frame frame = Frame::Base) {
        return done(MCM_HPP_FN(set_cartesian_velocity)(h(), linear.data(), angular.data(),
                                                       static_cast<uint32_t>(frame)));
    }
    Result<void> move_axis(uint32_t axis, double target_deg, double velocity_factor) {
        return done(MCM_HPP_FN(move_axis)(h(), axis, target_deg, velocity_factor));
    }
    Result<MoveAllResult> move_all(const Six& targets_deg, double velocity_factor) {
        MoveAllResult r{};
        return with(MCM_HPP_FN(move_all)(h(), targets_deg.data(), velocity_factor, &r), r);
    }
    /// The TCP on a straight line; answered once the MCM has checked the whole path.
    Result<MoveLinearResult> move_linear(const MoveLinear& line) {
        MoveLinearResult r{};
        return with(MCM_HPP_FN(move_linear)(h(), &line, &r), r);
    }
    Result<void> pvt_points(const std::vector<PvtPoint>& points) {
        return done(MCM_HPP_FN(pvt_points)(h(), points.data(), points.size()));
    }
    /// The tool the arm carries (TCP and load), from the next cycle.
    Result<void> set_tool(const Tool& tool) { return done(MCM_HPP_FN(set_tool)(h(), &tool)); }
    /// Estimate the load on the flange (the arm moves, under 30 s); with apply it becomes
    /// the tool's load.
    Result<Payload> identify_payload(bool apply = false) {
        Payload r{};
        return with(MCM_HPP_FN(identify_payload)(h(), apply, &r), r);
    }
    Result<void> take_control() { return done(MCM_HPP_FN(take_control)(h())); }
    Result<void> release_control() { return done(MCM_HPP_FN(release_control)(h())); }
    /// Read the state until pred(state) holds, at most timeout_s.
    template <class F>
    Result<Observed> wait_until(const std::string& what, double timeout_s, F pred) {
        Predicate<F, Observed> p(&pred);
        Observed s{};
        const mcm_error_t c = MCM_HPP_FN(wait_until)(h(), what.c_str(), timeout_s,
                                                &Predicate<F, Observed>::call, &p, &s);
        p.rethrow();
        return with(c, s);
    }

protected:
    explicit Client(H* h) : h_(h) {}
    H* h() const noexcept { return h_.get(); }
    Error error(mcm_error_t c) const {
        return Error(c, MCM_HPP_FN(last_reject)(h()), MCM_HPP_FN(last_error)(h()));
    }
    Result<void> done(mcm_error_t c) const {
        if (c != MCM_OK) return error(c);
        return {};
    }
    template <class T>
    Result<T> with(mcm_error_t c, const T& v) const {
        if (c != MCM_OK) return error(c);
        return v;
    }
    /// Call `call` with a Status to fill over TCP, without over shared memory.
    template <class F>
    Result<ModeAnswer> mode(F call) {
        if constexpr (kTcp) {
            Status s{};
            return with(call(&s), s);
        } else {
            return done(call());
        }
    }

private:
    std::unique_ptr<H, Close> h_;
};

#undef MCM_HPP_FN
}  // namespace detail

/// A connection to the MCM's JSON port (TCP): every command of docs/protocol.md, blocking,
/// bounded. Move-only; the destructor closes the connection (what it controlled ends in HOLD).
/// The commands both transports have are detail::Client's.
class TcpClient : public detail::Client<mcm_tcp_client_t> {
public:
    /// Connect to "host:port" (e.g. "127.0.0.1:18010").
    static Result<TcpClient> connect(const std::string& addr) {
        mcm_tcp_client_t* h = nullptr;
        const mcm_error_t c = mcm_tcp_connect(addr.c_str(), &h);
        if (c != MCM_OK) return detail::thread_error(c);
        return TcpClient(h);
    }

    Result<Status> status() { return get<Status>(mcm_tcp_status); }
    Result<Status> status_detail() { return get<Status>(mcm_tcp_status_detail); }
    Result<void> authenticate(const std::string& secret) {
        return done(mcm_tcp_authenticate(h(), secret.c_str()));
    }
    Result<void> reconnect() { return done(mcm_tcp_reconnect(h())); }
    /// Every joint configuration [deg] that puts the TCP at `pose` (base frame), within the
    /// axis limits, the nearest to `seed_deg` (none: the present position) first. Nothing
    /// moves. Executed by the gateway: TCP only (docs/cartesian.md).
    Result<std::vector<Six>> inverse_kinematics(const Pose& pose,
                                                const std::optional<Six>& seed_deg = {}) {
        mcm_ik_solutions_t r{};
        const mcm_error_t c =
            mcm_tcp_inverse_kinematics(h(), &pose, seed_deg ? seed_deg->data() : nullptr, &r);
        if (c != MCM_OK) return error(c);
        std::vector<Six> out(r.count);
        for (uint32_t i = 0; i < r.count; ++i) {
            for (size_t a = 0; a < MCM_NUM_AXES; ++a) out[i][a] = r.solutions[i][a];
        }
        return out;
    }
    /// A joint move (as move_all) to the solution of `pose` nearest the present position
    /// (PVT mode); the plan. Executed by the gateway: TCP only.
    Result<MoveAllResult> move_to_pose(const Pose& pose, double velocity_factor) {
        MoveAllResult r{};
        return with(mcm_tcp_move_to_pose(h(), &pose, velocity_factor, &r), r);
    }
    /// The next spontaneous message within timeout_s, or std::nullopt. Its `message` lives
    /// until the next call on this client.
    Result<std::optional<mcm_event_t>> next_event(double timeout_s) {
        mcm_event_t e{};
        bool got = false;
        const mcm_error_t c = mcm_tcp_next_event(h(), timeout_s, &e, &got);
        if (c != MCM_OK) return error(c);
        return got ? std::optional<mcm_event_t>(e) : std::nullopt;
    }

private:
    explicit TcpClient(mcm_tcp_client_t* h) : Client(h) {}
    template <class T, class Fn>
    Result<T> get(Fn fn) {
        T v{};
        return with(fn(h(), &v), v);
    }
};

/// A client of the real-time core's shared-memory services (same computer): each cycle's
/// state, commands into the next cycle, and the control loop. Move-only; not to be used from
/// another thread than the one that connected. The destructor tells the core the client is
/// gone (what it drove ends in HOLD). The commands both transports have are detail::Client's.
class ShmClient : public detail::Client<mcm_shm_client_t> {
public:
    /// Open the services of the MCM instance ("default" unless started with --instance).
    static Result<ShmClient> connect(const std::string& instance = "default") {
        mcm_shm_client_t* h = nullptr;
        const mcm_error_t c = mcm_shm_connect(instance.c_str(), &h);
        if (c != MCM_OK) return detail::thread_error(c);
        return ShmClient(h);
    }

    /// The next cycle's state (at most 0.5 s). Real-time safe.
    Result<State> wait_state() {
        State s{};
        return with(mcm_shm_wait_state(h(), &s), s);
    }
    Result<State> wait_state(double timeout_s) {
        State s{};
        return with(mcm_shm_wait_state_timeout(h(), timeout_s, &s), s);
    }
    /// The newest state without waiting. Real-time safe.
    Result<State> latest() {
        State s{};
        return with(mcm_shm_latest(h(), &s), s);
    }
    uint64_t client_id() {
        uint64_t id = 0;
        (void)mcm_shm_client_id(h(), &id);
        return id;
    }
    uint64_t missed_states() {
        uint64_t n = 0;
        (void)mcm_shm_missed_states(h(), &n);
        return n;
    }
    /// The oldest event not taken yet, or std::nullopt.
    Result<std::optional<mcm_event_t>> next_event() {
        mcm_event_t e{};
        bool got = false;
        const mcm_error_t c = mcm_shm_next_event(h(), &e, &got);
        if (c != MCM_OK) return error(c);
        return got ? std::optional<mcm_event_t>(e) : std::nullopt;
    }

    /// The control loop: `f(const mcm::State&, mcm::Output&) -> mcm::Control` is called with
    /// every cycle's state and fills the output (its `kind` preset from the mode: torques in
    /// TORQUE_CONTROL, velocities in VELOCITY_CONTROL, the next point in PVT); the answer is
    /// sent at once, to be applied in the next cycle. It runs until f returns Control::Finish
    /// (end ok) or the loop must end (end holds why: MCM_ERR_MODE_LEFT, MCM_ERR_SAFETY_TRIP,
    /// ...). An exception thrown by f ends the loop and is rethrown here.
    template <class F>
    ControlResult control(F&& f) {
        struct Ctx {
            explicit Ctx(std::remove_reference_t<F>* fn) : f(fn) {}
            std::remove_reference_t<F>* f;
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
            std::exception_ptr thrown;
#endif
        } ctx(&f);
        auto trampoline = [](const mcm_state_t* s, mcm_control_output_t* out,
                             void* user) noexcept -> int32_t {
            auto* c = static_cast<Ctx*>(user);
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
            try {
                return static_cast<int32_t>((*c->f)(*s, *out));
            } catch (...) {
                c->thrown = std::current_exception();
                return MCM_CONTROL_FINISH;
            }
#else
            return static_cast<int32_t>((*c->f)(*s, *out));
#endif
        };
        ControlResult r{ControlSummary{}, Result<void>()};
        const mcm_error_t c = mcm_shm_control(h(), trampoline, &ctx, &r.summary);
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
        if (ctx.thrown) std::rethrow_exception(ctx.thrown);
#endif
        if (c != MCM_OK) r.end = error(c);
        return r;
    }

private:
    explicit ShmClient(mcm_shm_client_t* h) : Client(h) {}
};

}  // namespace mcm

#endif  // MCM_MCM_HPP
