//! Command line shared by the `swarmctl-sitl` binary and `swarmctl sitl`:
//! how many vehicles, where, which flavour, and which faults.

mod fault_flags;

pub use fault_flags::FaultFlags;

use crate::config::{Flavour, VehicleConfig};
use crate::geo::GeoPoint;
use crate::swarm::{Swarm, spawn};
use anyhow::{Context, bail};
use std::net::IpAddr;
use std::time::Duration;

/// Run N mock autopilots until Ctrl-C (or benchmark them with --bench).
#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// Number of vehicles; vehicle i gets system id i+1 and port BASE_PORT+i.
    #[arg(long, default_value_t = 1)]
    pub vehicles: u8,
    /// Autopilot imitated: px4 or ardupilot.
    #[arg(long, default_value = "px4")]
    pub flavour: Flavour,
    /// UDP port of vehicle 1 (PX4's multi-vehicle convention); 0 picks ephemeral ports.
    #[arg(long, default_value_t = 14540)]
    pub base_port: u16,
    /// Address the vehicles listen on.
    #[arg(long, default_value = "127.0.0.1")]
    pub bind: IpAddr,
    /// Also stream all vehicles' messages to this UDP port (a ground station).
    #[arg(long)]
    pub gcs_port: Option<u16>,
    /// Fixed physics step rate, Hz.
    #[arg(long, default_value_t = 100.0)]
    pub physics_hz: f64,
    /// Position and attitude telemetry rate, Hz.
    #[arg(long, default_value_t = 20.0)]
    pub telemetry_hz: f64,
    /// Vehicles start in a row along east, this far apart (shared local NED frame), metres.
    #[arg(long, default_value_t = 2.0)]
    pub spacing_m: f32,
    /// Speed limit of every vehicle, m/s.
    #[arg(long, default_value_t = 5.0)]
    pub max_speed_mps: f32,
    /// Acceleration limit of every vehicle, m/s².
    #[arg(long, default_value_t = 3.0)]
    pub max_accel_mps2: f32,
    /// Seed of sensor noise and packet-loss draws (each vehicle adds its system id).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// PX4: after offboard loss, hold this long, then land, seconds; `inf`
    /// holds forever (PX4 with the offboard-loss action set to Hold).
    #[arg(long, default_value_t = 5.0)]
    pub offboard_loss_land_after_s: f64,
    /// MAVLink 2 signing key for all vehicles, 64 hex digits.
    #[arg(long)]
    pub signing_key: Option<String>,
    /// The faults to inject (`--fault`, and the older one-kind flags).
    #[command(flatten)]
    pub faults: FaultFlags,
    /// Benchmark instead of serving: run this many seconds with an in-process
    /// ground station receiving all telemetry, then report CPU use and missed ticks.
    #[arg(long, value_name = "SECONDS")]
    pub bench: Option<f64>,
}

/// Seconds as a duration; +∞ is [`Duration::MAX`], negative or NaN is an error.
fn seconds_f64(value: f64) -> anyhow::Result<Duration> {
    if value == f64::INFINITY {
        return Ok(Duration::MAX);
    }
    Ok(Duration::try_from_secs_f64(value)?)
}

/// Parses a 64-hex-digit signing key.
fn signing_key(hex: &str) -> anyhow::Result<[u8; 32]> {
    let hex = hex.trim();
    if hex.len() != 64 || !hex.is_ascii() {
        bail!("signing key must be 64 hex digits");
    }
    let mut key = [0u8; 32];
    for (i, byte) in key.iter_mut().enumerate() {
        *byte =
            u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).context("signing key must be hex")?;
    }
    Ok(key)
}

impl Args {
    /// The vehicle configurations these arguments describe.
    pub fn vehicle_configs(&self) -> anyhow::Result<Vec<VehicleConfig>> {
        let ids: Vec<u8> = (1..=self.vehicles).collect();
        let mut faults = self.faults.per_vehicle(&ids)?.into_iter();
        let key = self.signing_key.as_deref().map(signing_key).transpose()?;
        let land_after = seconds_f64(self.offboard_loss_land_after_s)
            .context("bad --offboard-loss-land-after-s")?;
        ids.iter()
            .enumerate()
            .map(|(i, id)| {
                let port = if self.base_port == 0 {
                    0
                } else {
                    u16::try_from(usize::from(self.base_port) + i)
                        .context("port number beyond 65535")?
                };
                let mut c = VehicleConfig::new(*id, self.flavour)
                    .at(GeoPoint::default(), [0.0, self.spacing_m * i as f32, 0.0]);
                c.port = port;
                c.max_speed_mps = self.max_speed_mps;
                c.max_accel_mps2 = self.max_accel_mps2;
                c.faults = faults.next().unwrap_or_default();
                c.signing_key = key;
                c.seed = self.seed.wrapping_add(u64::from(*id));
                c.gcs_stream_port = self.gcs_port;
                c.offboard_loss_land_after = land_after;
                Ok(c)
            })
            .collect()
    }
}

/// Runs the swarm until Ctrl-C, or the benchmark if `--bench` was given.
pub fn run(args: Args) -> anyhow::Result<()> {
    let configs = args.vehicle_configs()?;
    let runtime = tokio::runtime::Runtime::new().context("cannot start the tokio runtime")?;
    runtime.block_on(async move {
        match args.bench {
            Some(seconds) => {
                crate::bench::run(
                    args.bind,
                    configs,
                    args.physics_hz,
                    args.telemetry_hz,
                    seconds,
                )
                .await
            }
            None => serve(&args, configs).await,
        }
    })
}

async fn serve(args: &Args, configs: Vec<VehicleConfig>) -> anyhow::Result<()> {
    let swarm: Swarm = spawn(args.bind, configs, args.physics_hz, args.telemetry_hz).await?;
    for (i, address) in swarm.addresses().iter().enumerate() {
        let s = swarm.snapshot(i);
        println!(
            "vehicle sysid {} ({}) listening on {address}: connect with udpout:{address}",
            s.system_id, s.flavour
        );
    }
    let n = swarm.len();
    println!(
        "{n} {} running; Ctrl-C to stop",
        if n == 1 { "vehicle" } else { "vehicles" }
    );
    tokio::signal::ctrl_c()
        .await
        .context("waiting for Ctrl-C")?;
    swarm.shutdown().await;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::LinkDrop;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        args: Args,
    }

    fn parse(line: &[&str]) -> anyhow::Result<Vec<VehicleConfig>> {
        let cli = Cli::try_parse_from(std::iter::once("sitl").chain(line.iter().copied()))?;
        cli.args.vehicle_configs()
    }

    #[test]
    fn fault_flags_reach_the_right_vehicles() -> anyhow::Result<()> {
        let configs = parse(&[
            "--vehicles",
            "4",
            "--base-port",
            "15000",
            "--loss",
            "10",
            "--loss",
            "2:30",
            "--latency-ms",
            "50",
            "--slow",
            "3:0.5",
            "--drop",
            "4@5s+3s",
            "--refuse-arm",
            "1",
            "--low-battery",
            "2@60s",
            "--critical-battery",
            "2@90s",
            "--duplicate",
            "5",
            "--duplicate",
            "3:20",
            "--reorder",
            "4:15",
            "--offboard-loss-land-after-s",
            "inf",
        ])?;
        assert_eq!(
            configs.iter().map(|c| c.port).collect::<Vec<_>>(),
            [15000, 15001, 15002, 15003]
        );
        assert_eq!(
            configs.iter().map(|c| c.system_id).collect::<Vec<_>>(),
            [1, 2, 3, 4]
        );
        assert_eq!(configs[0].faults.loss_percent, 10.0);
        assert_eq!(configs[1].faults.loss_percent, 30.0);
        assert!(
            configs
                .iter()
                .all(|c| c.faults.latency == Duration::from_millis(50))
        );
        assert_eq!(configs[2].faults.speed_factor, 0.5);
        assert_eq!(
            configs[3].faults.link_drop,
            Some(LinkDrop {
                after_takeoff: Duration::from_secs(5),
                duration: Duration::from_secs(3)
            })
        );
        assert!(configs[0].faults.refuse_arm && !configs[1].faults.refuse_arm);
        assert_eq!(
            configs[1].faults.low_battery_after,
            Some(Duration::from_secs(60))
        );
        assert_eq!(
            configs[1].faults.critical_battery_after,
            Some(Duration::from_secs(90))
        );
        assert_eq!(
            configs
                .iter()
                .map(|c| c.faults.duplicate_percent)
                .collect::<Vec<_>>(),
            [5.0, 5.0, 20.0, 5.0]
        );
        assert_eq!(
            configs
                .iter()
                .map(|c| c.faults.reorder_percent)
                .collect::<Vec<_>>(),
            [0.0, 0.0, 0.0, 15.0]
        );
        assert!(
            configs
                .iter()
                .all(|c| c.offboard_loss_land_after == Duration::MAX)
        );
        assert_eq!(configs[1].initial_position_ned_m, [0.0, 2.0, 0.0]);
        Ok(())
    }

    #[test]
    fn permanent_drops_parse_as_duration_max() -> anyhow::Result<()> {
        for spec in ["1@2s+inf", "1@2s+never", "1@2s+forever"] {
            let configs = parse(&["--drop", spec])?;
            assert_eq!(
                configs[0].faults.link_drop,
                Some(LinkDrop::permanent(Duration::from_secs(2))),
                "{spec}"
            );
        }
        Ok(())
    }

    #[test]
    fn fault_flags_name_vehicles_by_system_id() -> anyhow::Result<()> {
        let configs = parse(&[
            "--vehicles",
            "3",
            "--fault",
            "loss=2:25%",
            "--fault",
            "lose=3@4s",
            "--fault",
            "low-battery=1@10s",
        ])?;
        assert_eq!(configs[1].faults.loss_percent, 25.0);
        assert_eq!(configs[0].faults.loss_percent, 0.0);
        assert_eq!(
            configs[2].faults.link_drop,
            Some(LinkDrop::permanent(Duration::from_secs(4)))
        );
        assert_eq!(
            configs[0].faults.critical_battery_after,
            Some(Duration::from_secs(55))
        );
        Ok(())
    }

    #[test]
    fn fault_errors_name_the_flag_and_the_problem() {
        for (line, said) in [
            (
                &["--drop", "9@1s+1s"][..],
                "--drop 9@1s+1s: no vehicle with system id 9",
            ),
            (&["--loss", "1:abc"], "--loss 1:abc: loss is not a number"),
            (&["--fault", "wind=3"], "--fault wind=3: unknown fault kind"),
            (
                &["--slow", "1:2"],
                "--slow 1:2: speed factor must be in (0, 1]",
            ),
        ] {
            let error = parse(line).map(|_| ()).unwrap_err().to_string();
            assert!(error.starts_with(said), "{line:?}: {error}");
        }
    }

    #[test]
    fn bad_fault_flags_are_errors_not_panics() {
        for line in [
            &["--slow", "0.5"][..],
            &["--drop", "1@5s"],
            &["--drop", "9@1s+1s"],
            &["--low-battery", "x@1s"],
            &["--loss", "1:abc"],
            &["--signing-key", "abcd"],
            &["--signing-key", "é"],
            &["--latency-ms", "-5"],
            &["--drop", "1@1s+-inf"],
            &["--drop", "1@1s+nan"],
            &["--critical-battery", "1"],
            &["--duplicate", "7:5"],
            &["--reorder", "x"],
            &["--offboard-loss-land-after-s", "-1"],
        ] {
            assert!(parse(line).is_err(), "{line:?} should be rejected");
        }
        let key = "00".repeat(31) + "ff";
        let configs = parse(&["--signing-key", &key]).expect("valid key");
        assert_eq!(configs[0].signing_key.map(|k| k[31]), Some(0xff));
    }
}
