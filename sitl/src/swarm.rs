//! Starting N vehicles in one process: one socket and receive task per
//! vehicle, and a single physics ticker that steps every vehicle and sends
//! due telemetry. One ticker instead of N timers is what lets 200 vehicles
//! run at 100 Hz on a fraction of a core.

use crate::config::{Flavour, VehicleConfig};
use crate::error::SitlError;
use crate::link::{self, Link, LinkStats};
use crate::mode::FlightMode;
pub use crate::setpoint_intervals::SetpointIntervals;
use crate::vehicle::Vehicle;
use mavlink::dialects::common::{MavLandedState, MavMessage};
use std::collections::HashSet;
use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, SocketAddr};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;
use tokio::net::UdpSocket;
use tokio::sync::mpsc;
use tokio::task::JoinHandle;
use tokio::time::{Instant, MissedTickBehavior};

/// A late ticker catches up at most this many steps at once; beyond that
/// simulated time slips behind wall time (and the ticks count as missed).
const MAX_CATCH_UP_STEPS: u64 = 25;

/// Largest datagram we read; MAVLink frames are at most 280 bytes.
const RECEIVE_BUFFER_BYTES: usize = 2048;

/// Fastest physics rate accepted, Hz.
const MAX_PHYSICS_RATE_HZ: f64 = 1000.0;

/// State shared between the tasks of one vehicle.
struct VehicleCell {
    vehicle: Mutex<Vehicle>,
    link: Arc<Link>,
    setpoint_intervals: Mutex<SetpointIntervals>,
}

impl VehicleCell {
    fn vehicle(&self) -> std::sync::MutexGuard<'_, Vehicle> {
        self.vehicle.lock().unwrap_or_else(PoisonError::into_inner)
    }

    fn setpoint_intervals(&self) -> std::sync::MutexGuard<'_, SetpointIntervals> {
        self.setpoint_intervals
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
    }
}

/// Real-time health of the physics ticker.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TickStats {
    /// Ticks the ticker woke up for.
    pub ticks: u64,
    /// Fixed physics steps integrated (ticks plus catch-up steps).
    pub steps: u64,
    /// Steps that were late by at least one whole period (caught up or skipped).
    pub missed_ticks: u64,
    /// Steps skipped entirely because the ticker fell too far behind.
    pub skipped_steps: u64,
}

#[derive(Default)]
struct AtomicTickStats {
    ticks: AtomicU64,
    steps: AtomicU64,
    missed_ticks: AtomicU64,
    skipped_steps: AtomicU64,
}

/// What a test can observe of a vehicle: the true state, not the noisy telemetry.
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleSnapshot {
    /// MAVLink system id.
    pub system_id: u8,
    /// Autopilot flavour.
    pub flavour: Flavour,
    /// Address the vehicle listens on.
    pub address: SocketAddr,
    /// True position, shared local NED frame, metres.
    pub position_ned_m: [f32; 3],
    /// True velocity, NED, m/s.
    pub velocity_ned_mps: [f32; 3],
    /// Heading, radians from north.
    pub yaw_rad: f32,
    /// Motors armed.
    pub armed: bool,
    /// Flight mode.
    pub mode: FlightMode,
    /// HEARTBEAT custom_mode as sent on the wire.
    pub custom_mode: u32,
    /// Resting on the ground.
    pub landed: bool,
    /// Landed state as EXTENDED_SYS_STATE reports it.
    pub landed_state: MavLandedState,
    /// Battery charge, percent.
    pub battery_remaining_pct: f32,
    /// The low-battery warning has fired (also true once critical).
    pub battery_low: bool,
    /// The critical-battery failsafe has fired.
    pub battery_critical: bool,
    /// An injected link drop is active.
    pub link_down: bool,
    /// Simulated time since start, seconds.
    pub time_s: f64,
    /// Link counters.
    pub link: LinkStats,
}

/// A running swarm of mock vehicles. Dropping it stops every task.
pub struct Swarm {
    cells: Vec<Arc<VehicleCell>>,
    tasks: Vec<JoinHandle<()>>,
    tick_stats: Arc<AtomicTickStats>,
}

/// Binds one UDP socket per vehicle on `bind_ip` and starts them all.
///
/// Must be called inside a tokio runtime. Physics runs at `physics_rate_hz`
/// (fixed step), position and attitude telemetry at `telemetry_rate_hz`.
pub async fn spawn(
    bind_ip: IpAddr,
    vehicles: Vec<VehicleConfig>,
    physics_rate_hz: f64,
    telemetry_rate_hz: f64,
) -> Result<Swarm, SitlError> {
    validate(&vehicles, physics_rate_hz, telemetry_rate_hz)?;
    let mut cells = Vec::with_capacity(vehicles.len());
    let mut tasks = Vec::with_capacity(vehicles.len() * 3 + 1);
    for config in vehicles {
        let (cell, mut cell_tasks) = start_vehicle(bind_ip, config, telemetry_rate_hz).await?;
        cells.push(cell);
        tasks.append(&mut cell_tasks);
    }
    let tick_stats = Arc::new(AtomicTickStats::default());
    tasks.push(tokio::spawn(run_physics(
        cells.clone(),
        1.0 / physics_rate_hz,
        tick_stats.clone(),
    )));
    Ok(Swarm {
        cells,
        tasks,
        tick_stats,
    })
}

fn validate(
    vehicles: &[VehicleConfig],
    physics_rate_hz: f64,
    telemetry_rate_hz: f64,
) -> Result<(), SitlError> {
    for (what, value) in [
        ("physics rate (Hz)", physics_rate_hz),
        ("telemetry rate (Hz)", telemetry_rate_hz),
    ] {
        if !(value.is_finite() && value > 0.0 && value <= MAX_PHYSICS_RATE_HZ) {
            return Err(SitlError::InvalidRate { what, value });
        }
    }
    let mut seen = HashSet::new();
    for v in vehicles {
        if v.system_id == 0 {
            return Err(SitlError::ZeroSystemId);
        }
        if !seen.insert(v.system_id) {
            return Err(SitlError::DuplicateSystemId(v.system_id));
        }
        v.faults.validate(v.system_id)?;
        for (what, value) in [
            ("max speed (m/s)", v.max_speed_mps),
            ("max acceleration (m/s²)", v.max_accel_mps2),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(SitlError::InvalidRate {
                    what,
                    value: f64::from(value),
                });
            }
        }
    }
    Ok(())
}

/// Where "the ground station on this machine" is for a bind address.
fn gcs_address(bind_ip: IpAddr, port: u16) -> SocketAddr {
    let ip = match bind_ip {
        IpAddr::V4(v4) if v4.is_unspecified() => IpAddr::V4(Ipv4Addr::LOCALHOST),
        IpAddr::V6(v6) if v6.is_unspecified() => IpAddr::V6(Ipv6Addr::LOCALHOST),
        ip => ip,
    };
    SocketAddr::new(ip, port)
}

async fn start_vehicle(
    bind_ip: IpAddr,
    config: VehicleConfig,
    telemetry_rate_hz: f64,
) -> Result<(Arc<VehicleCell>, Vec<JoinHandle<()>>), SitlError> {
    let system_id = config.system_id;
    let address = SocketAddr::new(bind_ip, config.port);
    let bind_error = |source| SitlError::Bind {
        system_id,
        address,
        source,
    };
    let socket = UdpSocket::bind(address).await.map_err(bind_error)?;
    let local_address = socket.local_addr().map_err(bind_error)?;
    let socket = Arc::new(socket);
    let mut tasks = Vec::new();
    let delayed = link::needs_delay_queue(&config.faults);
    let (tx_queue, tx_receiver) = if delayed {
        let (s, r) = mpsc::unbounded_channel();
        (Some(s), Some(r))
    } else {
        (None, None)
    };
    let link = Arc::new(Link::new(
        system_id,
        socket,
        local_address,
        config.gcs_stream_port.map(|p| gcs_address(bind_ip, p)),
        &config.faults,
        config.seed,
        config.signing_key,
        tx_queue,
    ));
    if let Some(receiver) = tx_receiver {
        let sender = link.clone();
        tasks.push(tokio::spawn(link::run_delay_queue(
            receiver,
            move |bytes, addresses| sender.send_now(&bytes, &addresses),
        )));
    }
    let cell = Arc::new(VehicleCell {
        vehicle: Mutex::new(Vehicle::new(config, telemetry_rate_hz)),
        link,
        setpoint_intervals: Mutex::default(),
    });
    if delayed {
        let (s, r) = mpsc::unbounded_channel();
        tasks.push(tokio::spawn(run_receiver(cell.clone(), Some(s))));
        let delayed_cell = cell.clone();
        tasks.push(tokio::spawn(link::run_delay_queue(
            r,
            move |bytes, addresses| {
                if let Some(from) = addresses.first() {
                    deliver(&delayed_cell, &bytes, *from);
                }
            },
        )));
    } else {
        tasks.push(tokio::spawn(run_receiver(cell.clone(), None)));
    }
    Ok((cell, tasks))
}

/// Receives datagrams forever, applying loss/drop, duplication, then
/// latency and reordering, then delivery.
async fn run_receiver(
    cell: Arc<VehicleCell>,
    delay_queue: Option<mpsc::UnboundedSender<link::Delayed>>,
) {
    let mut buffer = vec![0u8; RECEIVE_BUFFER_BYTES];
    loop {
        let (len, from) = match cell.link.socket.recv_from(&mut buffer).await {
            Ok(received) => received,
            Err(error) => {
                // e.g. ICMP port-unreachable reported on the socket: transient.
                tracing::debug!(%error, "recv_from failed");
                tokio::time::sleep(Duration::from_millis(1)).await;
                continue;
            }
        };
        let Some(bytes) = buffer.get(..len) else {
            continue;
        };
        for delay in cell.link.admit_incoming().into_iter().flatten() {
            match &delay_queue {
                Some(queue) if !delay.is_zero() => {
                    link::delay_incoming(queue, delay, bytes.to_vec(), from);
                }
                _ => deliver(&cell, bytes, from),
            }
        }
    }
}

/// Decodes a datagram, lets the autopilot handle it and sends its replies.
fn deliver(cell: &VehicleCell, bytes: &[u8], from: SocketAddr) {
    let messages = cell.link.decode(bytes, from);
    if messages.is_empty() {
        return;
    }
    for (_, message) in &messages {
        if matches!(
            message,
            MavMessage::SET_POSITION_TARGET_LOCAL_NED(_)
                | MavMessage::SET_POSITION_TARGET_GLOBAL_INT(_)
        ) {
            cell.setpoint_intervals().arrived(Instant::now());
        }
    }
    let replies = {
        let mut vehicle = cell.vehicle();
        for (header, message) in &messages {
            vehicle.handle(*header, message);
        }
        std::mem::take(&mut vehicle.outbox)
    };
    cell.link.send(&replies);
}

/// The single fixed-rate ticker: steps all vehicles, then sends their telemetry.
async fn run_physics(cells: Vec<Arc<VehicleCell>>, dt_s: f64, stats: Arc<AtomicTickStats>) {
    let mut interval = tokio::time::interval(Duration::from_secs_f64(dt_s));
    interval.set_missed_tick_behavior(MissedTickBehavior::Skip);
    let start = Instant::now();
    let mut steps_done: u64 = 0;
    let mut outgoing = Vec::new();
    loop {
        interval.tick().await;
        let due = (start.elapsed().as_secs_f64() / dt_s) as u64 + 1;
        let behind = due.saturating_sub(steps_done);
        if behind > 1 {
            stats.missed_ticks.fetch_add(behind - 1, Ordering::Relaxed);
        }
        let steps = behind.min(MAX_CATCH_UP_STEPS);
        stats
            .skipped_steps
            .fetch_add(behind - steps, Ordering::Relaxed);
        steps_done = due;
        for cell in &cells {
            {
                let mut vehicle = cell.vehicle();
                for _ in 0..steps {
                    vehicle.step(dt_s);
                }
                vehicle.queue_due_telemetry();
                cell.link.set_down(vehicle.link_down());
                std::mem::swap(&mut outgoing, &mut vehicle.outbox);
            }
            cell.link.send(&outgoing);
            outgoing.clear();
        }
        stats.ticks.fetch_add(1, Ordering::Relaxed);
        stats.steps.fetch_add(steps, Ordering::Relaxed);
    }
}

impl Swarm {
    /// Where each vehicle listens, in the order given to [`spawn`]. A
    /// controller talks to vehicle i with `udpout:` to `addresses()[i]`.
    pub fn addresses(&self) -> Vec<SocketAddr> {
        self.cells.iter().map(|c| c.link.local_address).collect()
    }

    /// Number of vehicles.
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// Whether the swarm has no vehicles.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// True state of vehicle `index` (the order given to [`spawn`]).
    ///
    /// # Panics
    /// If `index >= self.len()`, like slice indexing.
    pub fn snapshot(&self, index: usize) -> VehicleSnapshot {
        let cell = &self.cells[index];
        let v = cell.vehicle();
        VehicleSnapshot {
            system_id: v.system_id,
            flavour: v.flavour,
            address: cell.link.local_address,
            position_ned_m: v.body.position_ned_m,
            velocity_ned_mps: v.body.velocity_ned_mps,
            yaw_rad: v.body.yaw_rad,
            armed: v.armed,
            mode: v.mode,
            custom_mode: v.custom_mode(),
            landed: v.landed(),
            landed_state: v.landed_state(),
            battery_remaining_pct: v.battery_pct,
            battery_low: v.battery_low,
            battery_critical: v.battery_critical,
            link_down: v.link_down(),
            time_s: v.time_s,
            link: cell.link.stats(),
        }
    }

    /// The system ids of the vehicles armed now, by truth: what a flight that
    /// ended should leave empty.
    pub fn armed_system_ids(&self) -> Vec<u8> {
        (0..self.len())
            .map(|i| self.snapshot(i))
            .filter(|s| s.armed)
            .map(|s| s.system_id)
            .collect()
    }

    /// Wall-clock intervals between the setpoints vehicle `index` received.
    ///
    /// # Panics
    /// If `index >= self.len()`, like slice indexing.
    pub fn setpoint_intervals(&self, index: usize) -> SetpointIntervals {
        self.cells[index].setpoint_intervals().histogram()
    }

    /// Counters of the physics ticker (real-time health).
    pub fn tick_stats(&self) -> TickStats {
        let s = &self.tick_stats;
        TickStats {
            ticks: s.ticks.load(Ordering::Relaxed),
            steps: s.steps.load(Ordering::Relaxed),
            missed_ticks: s.missed_ticks.load(Ordering::Relaxed),
            skipped_steps: s.skipped_steps.load(Ordering::Relaxed),
        }
    }

    /// Stops every task and closes the sockets.
    pub async fn shutdown(mut self) {
        let tasks = std::mem::take(&mut self.tasks);
        for task in &tasks {
            task.abort();
        }
        for task in tasks {
            // An aborted task reports a cancellation error, which is the point.
            let _ = task.await;
        }
    }
}

impl Drop for Swarm {
    fn drop(&mut self) {
        for task in &self.tasks {
            task.abort();
        }
    }
}
