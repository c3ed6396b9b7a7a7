//! Packs a little-endian `f32` row-major grid into the project's lossless `.dem.cc` format (see
//! `curvicast_host::scenes::real_dem`): `cargo run --example pack_dem -- IN.f32 ROWS COLS SCALE OUT.dem.cc`.

use curvicast_host::scenes::real_dem::{decode, encode};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let [_, input, rows, cols, scale, output] = args.as_slice() else {
        anyhow::bail!("usage: pack_dem IN.f32 ROWS COLS SCALE OUT.dem.cc");
    };
    let (rows, cols, scale): (usize, usize, u32) = (rows.parse()?, cols.parse()?, scale.parse()?);
    let bytes = std::fs::read(input)?;
    let heights: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let packed = encode(rows, cols, scale, &heights).map_err(anyhow::Error::msg)?;
    let (_, _, back) = decode(&packed).map_err(anyhow::Error::msg)?;
    anyhow::ensure!(back == heights, "round trip differs");
    std::fs::write(output, &packed)?;
    println!(
        "{output}: {} bytes ({} heights)",
        packed.len(),
        heights.len()
    );
    Ok(())
}
