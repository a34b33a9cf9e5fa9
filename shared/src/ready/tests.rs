//! Every ready line reads back as the value it was printed from, and a wrong line is refused
//! naming what is wrong.

use super::*;
use proptest::prelude::*;

fn addr() -> impl Strategy<Value = SocketAddr> {
    prop_oneof![
        (any::<[u8; 4]>(), any::<u16>()).prop_map(|(ip, port)| SocketAddr::from((ip, port))),
        (any::<[u16; 8]>(), any::<u16>()).prop_map(|(ip, port)| SocketAddr::from((ip, port))),
    ]
}

fn instance() -> impl Strategy<Value = String> {
    "[A-Za-z0-9_-]{1,32}"
}

fn gateway() -> impl Strategy<Value = GatewayReady> {
    let endpoint = prop_oneof![
        addr().prop_map(|a| format!("tcp://{a}")),
        "ipc:///tmp/[a-z]{1,8}",
    ];
    let zmq = prop::option::of((endpoint.clone(), endpoint))
        .prop_map(|z| z.map(|(router, publish)| ZmqEndpoints { router, publish }));
    (addr(), addr(), prop::option::of(addr()), zmq).prop_map(|(json, hmi, web, zmq)| GatewayReady {
        json,
        hmi,
        web,
        zmq,
    })
}

proptest! {
    #[test]
    fn rt_lines_round_trip(instance in instance(), sim in any::<bool>()) {
        let bus = if sim { BusBackend::Sim } else { BusBackend::Socketcan };
        let ready = RtReady { instance, bus };
        let line = ready.to_string();
        prop_assert!(line.starts_with(RtReady::PREFIX));
        prop_assert_eq!(line.parse::<RtReady>(), Ok(ready));
    }

    #[test]
    fn ros2_lines_round_trip(
        node in "(/[a-z][a-z0-9_]{0,8}){1,3}",
        domain in 0u16..=232,
        instance in instance(),
    ) {
        let ready = Ros2Ready { node, domain, instance };
        let line = ready.to_string();
        prop_assert!(line.starts_with(Ros2Ready::PREFIX));
        prop_assert_eq!(line.parse::<Ros2Ready>(), Ok(ready));
    }

    #[test]
    fn virtual_arm_lines_round_trip(
        interface in "[a-z][a-z0-9]{0,14}",
        port in 1u16..,
    ) {
        let control = std::net::SocketAddr::from(([127, 0, 0, 1], port));
        let ready = VirtualArmReady { interface, control };
        let line = ready.to_string();
        prop_assert!(line.starts_with(VirtualArmReady::PREFIX));
        prop_assert_eq!(line.parse::<VirtualArmReady>(), Ok(ready));
    }

    #[test]
    fn gateway_lines_round_trip(ready in gateway()) {
        let line = ready.to_string();
        prop_assert!(line.starts_with(GatewayReady::PREFIX));
        prop_assert_eq!(line.parse::<GatewayReady>(), Ok(ready));
    }

    /// Any robot words without control characters, brackets, parentheses and the words of
    /// the line itself included.
    #[test]
    fn launcher_lines_round_trip(
        robot in "[^\\p{Cc}]{0,40}",
        instance in instance(),
        gateway in gateway(),
        rt_pid in any::<u32>(),
        gateway_pid in any::<u32>(),
    ) {
        let ready = McmReady { robot, instance, gateway, rt_pid, gateway_pid };
        let line = ready.to_string();
        prop_assert!(line.starts_with(McmReady::PREFIX));
        prop_assert!(!line.contains('\n'));
        prop_assert_eq!(line.parse::<McmReady>(), Ok(ready));
    }
}

#[test]
fn the_lines_read_as_printed_so_far() {
    let rt: RtReady = "mcm-rt ready instance=default bus=sim".parse().unwrap();
    assert_eq!(rt.instance, "default");
    assert_eq!(rt.bus, BusBackend::Sim);
    let line = "MCM ready (simulated P-Rob2, instance b1): JSON on 127.0.0.1:4000, telnet HMI \
                on 127.0.0.1:4001; Ctrl-C stops. [instance=b1 robot=simulated%20P-Rob2 \
                json=127.0.0.1:4000 hmi=127.0.0.1:4001 rt_pid=12 gateway_pid=13]";
    let mcm: McmReady = line.parse().unwrap();
    assert_eq!(mcm.robot, "simulated P-Rob2");
    assert_eq!(mcm.gateway.hmi.port(), 4001);
    assert_eq!((mcm.rt_pid, mcm.gateway_pid), (12, 13));
    assert_eq!(mcm.to_string(), line);
}

/// A reader reads the fields only: other words for people, or none, read the same.
#[test]
fn the_launcher_s_words_may_change_without_breaking_a_reader() {
    let fields = "[instance=b1 robot=P-Rob2%20%5Blab%5D%25 json=127.0.0.1:4000 \
                  hmi=127.0.0.1:4001 rt_pid=12 gateway_pid=13]";
    for words in [
        "",
        "(the P-Rob2 is up; connect to port 4000) ",
        "(x [instance=y]) ",
    ] {
        let mcm: McmReady = format!("MCM ready {words}{fields}").parse().unwrap();
        assert_eq!(mcm.robot, "P-Rob2 [lab]%", "{words}");
        assert_eq!((mcm.instance.as_str(), mcm.rt_pid), ("b1", 12), "{words}");
    }
    let e = "MCM ready [instance=b1 robot=a%2 json=1.2.3.4:5 hmi=1.2.3.4:6 rt_pid=1 \
             gateway_pid=2]"
        .parse::<McmReady>()
        .unwrap_err();
    assert!(e.to_string().contains("`robot=a%2`"), "{e}");
}

#[test]
fn a_robot_name_cannot_put_control_characters_in_the_line() {
    let ready = McmReady {
        robot: "simulated P-Rob2\x1b[2J\n".into(),
        instance: "x".into(),
        gateway: "mcm-gateway ready json=127.0.0.1:1 hmi=127.0.0.1:2"
            .parse()
            .unwrap(),
        rt_pid: 1,
        gateway_pid: 2,
    };
    let line = ready.to_string();
    assert!(
        line.starts_with("MCM ready (simulated P-Rob2?[2J?, instance x)"),
        "{line}"
    );
    assert_eq!(
        line.parse::<McmReady>().unwrap().robot,
        "simulated P-Rob2?[2J?"
    );
}

#[test]
fn wrong_lines_are_refused_naming_what_is_wrong() {
    let e = "mcm-rt ready instance=a bus=can"
        .parse::<RtReady>()
        .unwrap_err();
    assert!(
        e.to_string()
            .contains("`bus=can` is not `sim` or `socketcan`"),
        "{e}"
    );
    let e = "mcm-gateway ready hmi=1.2.3.4:5"
        .parse::<GatewayReady>()
        .unwrap_err();
    assert_eq!(
        e,
        ReadyError::Missing {
            key: "json",
            line: "mcm-gateway ready hmi=1.2.3.4:5".into()
        }
    );
    let e = "mcm-gateway ready json=here hmi=1.2.3.4:5"
        .parse::<GatewayReady>()
        .unwrap_err();
    assert!(
        e.to_string()
            .contains("`json=here` is not an address and port"),
        "{e}"
    );
    let e = "mcm-gateway ready json=1.2.3.4:5 hmi=1.2.3.4:6 zmq_router=tcp://a:1"
        .parse::<GatewayReady>()
        .unwrap_err();
    assert!(e.to_string().contains("no `zmq_publish=`"), "{e}");
    let e = "mcm-gateway: cannot listen"
        .parse::<GatewayReady>()
        .unwrap_err();
    assert!(matches!(e, ReadyError::NotReady { .. }), "{e}");
    // Unknown keys are ignored: a newer program may print more.
    let g: GatewayReady = "mcm-gateway ready json=1.2.3.4:5 hmi=1.2.3.4:6 new=1"
        .parse()
        .unwrap();
    assert_eq!(g.json.port(), 5);
}

#[test]
fn a_ros2_line_with_a_bad_domain_is_refused_naming_it() {
    let line = "mcm-ros2 ready node=/mcm domain=999 instance=default";
    let e = line.parse::<Ros2Ready>().unwrap_err();
    assert!(
        e.to_string()
            .contains("`domain=999` is not a DDS domain id"),
        "{e}"
    );
}
