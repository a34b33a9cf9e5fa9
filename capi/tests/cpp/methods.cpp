// Every method of mcm.hpp's one command set, compiled for both handles (an explicit
// instantiation compiles each member, used by an example or not), with the answers each
// transport gives. Compiled by capi/tests/cpp_header.rs; never run.
#include "mcm/mcm.hpp"

#include <type_traits>
#include <utility>

template class mcm::detail::Client<mcm_tcp_client_t>;
template class mcm::detail::Client<mcm_shm_client_t>;

static_assert(std::is_same_v<decltype(std::declval<mcm::TcpClient&>().hold()),
                             mcm::Result<mcm::Status>>,
              "over TCP a mode change answers the state");
static_assert(std::is_same_v<decltype(std::declval<mcm::ShmClient&>().hold()),
                             mcm::Result<void>>,
              "over shared memory a mode change answers nothing");
static_assert(std::is_same_v<decltype(std::declval<mcm::TcpClient&>().info()),
                             mcm::Result<mcm::Info>>);
static_assert(std::is_same_v<decltype(std::declval<mcm::ShmClient&>().info()),
                             mcm::Result<mcm::ShmInfo>>);
static_assert(!std::is_copy_constructible_v<mcm::TcpClient> &&
              std::is_nothrow_move_constructible_v<mcm::ShmClient>);

// The template members, with a predicate of each transport's state.
void wait_until(mcm::TcpClient& t, mcm::ShmClient& s) {
    (void)t.wait_until("tcp", 1.0, [](const mcm::Status& st) { return st.mode != 0; });
    (void)s.wait_until("shm", 1.0, [](const mcm::State& st) { return st.seq != 0; });
}

// The Cartesian commands the gateway executes: methods of TcpClient only.
void cartesian(mcm::TcpClient& t) {
    const mcm::Pose pose{{0.3, 0.0, 0.5}, {0.0, 1.0, 0.0, 0.0}};
    static_assert(std::is_same_v<decltype(t.inverse_kinematics(pose)),
                                 mcm::Result<std::vector<mcm::Six>>>);
    (void)t.inverse_kinematics(pose, mcm::Six{});
    (void)t.move_to_pose(pose, 0.5);
}

// Over shared memory there is no gateway: ShmClient has no inverse_kinematics (a compile
// error, not a call that fails at run time).
template <class C, class = void>
struct HasInverseKinematics : std::false_type {};
template <class C>
struct HasInverseKinematics<C, std::void_t<decltype(std::declval<C&>().inverse_kinematics(
                                   std::declval<const mcm::Pose&>()))>> : std::true_type {};
static_assert(HasInverseKinematics<mcm::TcpClient>::value &&
              !HasInverseKinematics<mcm::ShmClient>::value);
