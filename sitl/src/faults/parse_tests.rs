use super::*;

#[test]
fn parses_every_kind() {
    assert_eq!(
        parse_fault("loss=10%"),
        Ok(FaultSpec::Loss {
            drone: None,
            percent: 10.0
        })
    );
    assert_eq!(
        parse_fault("latency=50ms"),
        Ok(FaultSpec::Latency {
            drone: None,
            latency: Duration::from_millis(50)
        })
    );
    assert_eq!(
        parse_fault("slow=b1:0.5"),
        Ok(FaultSpec::Slow {
            drone: "b1".into(),
            factor: 0.5
        })
    );
    assert_eq!(
        parse_fault("drop=b1@5s+3s"),
        Ok(FaultSpec::Drop {
            drone: "b1".into(),
            after: Duration::from_secs(5),
            duration: Duration::from_secs(3)
        })
    );
    assert_eq!(
        parse_fault("refuse-arm=r2"),
        Ok(FaultSpec::RefuseArm { drone: "r2".into() })
    );
}

#[test]
fn parses_the_reliability_faults() {
    assert_eq!(
        parse_fault("dup=5%"),
        Ok(FaultSpec::Duplicate {
            drone: None,
            percent: 5.0
        })
    );
    assert_eq!(
        parse_fault("reorder=20%"),
        Ok(FaultSpec::Reorder {
            drone: None,
            percent: 20.0
        })
    );
    assert_eq!(
        parse_fault("lose=r2@8s"),
        Ok(FaultSpec::Lose {
            drone: "r2".into(),
            after: Duration::from_secs(8)
        })
    );
    assert_eq!(
        parse_fault("crash=b3@20s"),
        Ok(FaultSpec::Crash {
            drone: "b3".into(),
            after: Duration::from_secs(20)
        })
    );
    assert_eq!(
        parse_fault("low-battery=b1@12.5s"),
        Ok(FaultSpec::LowBattery {
            drone: "b1".into(),
            after: Duration::from_millis(12_500),
            critical_after: CRITICAL_AFTER_LOW,
        })
    );
    assert_eq!(
        parse_fault("critical-battery=b1@500ms"),
        Ok(FaultSpec::CriticalBattery {
            drone: "b1".into(),
            after: Duration::from_millis(500)
        })
    );
}

#[test]
fn link_faults_may_name_one_drone_and_spans_may_be_endless() {
    assert_eq!(
        parse_fault("loss=3:25%"),
        Ok(FaultSpec::Loss {
            drone: Some("3".into()),
            percent: 25.0
        })
    );
    assert_eq!(
        parse_fault("latency=b2:0.2s"),
        Ok(FaultSpec::Latency {
            drone: Some("b2".into()),
            latency: Duration::from_millis(200)
        })
    );
    for forever in ["inf", "never", "forever"] {
        assert_eq!(
            parse_fault(&format!("drop=b1@5s+{forever}")),
            Ok(FaultSpec::Drop {
                drone: "b1".into(),
                after: Duration::from_secs(5),
                duration: Duration::MAX
            })
        );
    }
    assert_eq!(
        parse_fault("low-battery=b1@10s+inf"),
        Ok(FaultSpec::LowBattery {
            drone: "b1".into(),
            after: Duration::from_secs(10),
            critical_after: Duration::MAX,
        })
    );
    assert_eq!(
        parse_fault("low-battery=b1@10s+30s").map(|f| f.drone().map(String::from)),
        Ok(Some("b1".into()))
    );
}

#[test]
fn malformed_flags_name_the_flag() {
    for flag in [
        "loss=10",
        "loss=x%",
        "loss=:10%",
        "slow=b1",
        "slow=b1:0",
        "slow=b1:2",
        "drop=b1@5s",
        "drop=b1@5s+-inf",
        "drop=b1@5s+nan",
        "latency=5",
        "latency=-5ms",
        "wind=3",
        "dup=5",
        "reorder=101%",
        "lose=b1",
        "lose=b1@inf",
        "low-battery=@5s",
        "low-battery=b1@5s+soon",
        "critical-battery=b1@soon",
        "refuse-arm=",
        "nothing",
    ] {
        let e = parse_fault(flag).unwrap_err();
        assert!(
            e.to_string().starts_with(&format!("--fault {flag}:")),
            "{e}"
        );
    }
}
