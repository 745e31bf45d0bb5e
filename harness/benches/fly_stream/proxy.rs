//! The receiving side of the `fly_stream` benchmark: one UDP relay per vehicle
//! in front of the bundled SITL that timestamps every SET_POSITION_TARGET_LOCAL_NED
//! the moment it arrives, then forwards the datagram unchanged (and relays the
//! vehicle's replies back to whoever spoke last).
//!
//! The relays run on their own OS thread and single-threaded runtime, apart from
//! the vehicles' runtime, so a busy physics tick does not delay a timestamp.

use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::Instant;
use tokio::net::UdpSocket;

/// MAVLink message id of SET_POSITION_TARGET_LOCAL_NED.
const SET_POSITION_TARGET_LOCAL_NED_ID: u32 = 84;

/// Arrival times of setpoints, one list per vehicle.
pub type Arrivals = Arc<Vec<Mutex<Vec<Instant>>>>;

/// The MAVLink message id of a datagram holding one frame (v1 or v2), if any.
pub fn message_id(datagram: &[u8]) -> Option<u32> {
    match datagram.first()? {
        0xFD if datagram.len() >= 10 => Some(
            u32::from(datagram[7]) | u32::from(datagram[8]) << 8 | u32::from(datagram[9]) << 16,
        ),
        0xFE if datagram.len() >= 6 => Some(u32::from(datagram[5])),
        _ => None,
    }
}

/// Starts one relay per vehicle address on 127.0.0.1 and returns the relay
/// ports (what the sender connects to) and the shared arrival lists.
pub fn start(vehicles: Vec<SocketAddr>) -> std::io::Result<(Vec<u16>, Arrivals)> {
    let arrivals: Arrivals = Arc::new(vehicles.iter().map(|_| Mutex::new(Vec::new())).collect());
    let (ports_tx, ports_rx) = std::sync::mpsc::channel();
    let shared = arrivals.clone();
    std::thread::spawn(move || {
        let runtime = match tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
        {
            Ok(r) => r,
            Err(e) => {
                let _ = ports_tx.send(Err(e));
                return;
            }
        };
        runtime.block_on(async move {
            let mut ports = Vec::new();
            for (index, vehicle) in vehicles.into_iter().enumerate() {
                match relay(index, vehicle, shared.clone()).await {
                    Ok(port) => ports.push(port),
                    Err(e) => {
                        let _ = ports_tx.send(Err(e));
                        return;
                    }
                }
            }
            let _ = ports_tx.send(Ok(ports));
            std::future::pending::<()>().await;
        });
    });
    let ports = ports_rx
        .recv()
        .map_err(|_| std::io::Error::other("relay thread stopped"))??;
    Ok((ports, arrivals))
}

/// One relay: front socket for the sender, back socket connected to the vehicle.
async fn relay(index: usize, vehicle: SocketAddr, arrivals: Arrivals) -> std::io::Result<u16> {
    let front = Arc::new(UdpSocket::bind("127.0.0.1:0").await?);
    let back = Arc::new(UdpSocket::bind("127.0.0.1:0").await?);
    back.connect(vehicle).await?;
    let port = front.local_addr()?.port();
    let sender: Arc<Mutex<Option<SocketAddr>>> = Arc::default();
    let (f, b, s) = (front.clone(), back.clone(), sender.clone());
    tokio::spawn(async move {
        let mut buf = [0u8; 512];
        loop {
            let Ok((n, peer)) = f.recv_from(&mut buf).await else {
                continue;
            };
            if message_id(&buf[..n]) == Some(SET_POSITION_TARGET_LOCAL_NED_ID) {
                let now = Instant::now();
                if let Some(list) = arrivals.get(index) {
                    list.lock().unwrap_or_else(|e| e.into_inner()).push(now);
                }
            }
            *s.lock().unwrap_or_else(|e| e.into_inner()) = Some(peer);
            let _ = b.send(&buf[..n]).await;
        }
    });
    tokio::spawn(async move {
        let mut buf = [0u8; 512];
        loop {
            let Ok(n) = back.recv(&mut buf).await else {
                continue;
            };
            let peer = *sender.lock().unwrap_or_else(|e| e.into_inner());
            if let Some(peer) = peer {
                let _ = front.send_to(&buf[..n], peer).await;
            }
        }
    });
    Ok(port)
}
