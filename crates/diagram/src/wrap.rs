//! Wrapping a rung wider than the page onto bands below one another, as
//! GX Works2 folds a long rung: each band ends where the next begins, and a
//! pair of numbered marks joins every wire that crosses the fold. The last
//! band keeps the outputs against the right rail.

use super::layout::{Connector, RungLayout, Wire};

/// `laid` folded to at most `width` columns (unchanged when it fits).
pub fn wrap(laid: RungLayout, width: u32) -> RungLayout {
    if laid.columns <= width || width < 3 {
        return laid;
    }
    let bands = bands(&laid, width);
    let mut out = RungLayout {
        columns: width,
        rows: 0,
        cells: Vec::new(),
        wires: Vec::new(),
        label: laid.label.clone(),
        connectors: Vec::new(),
    };
    let mut next_number = 1;
    // Marks of the fold before the band being placed: (row, number).
    let mut incoming: Vec<(u32, u32)> = Vec::new();
    for (k, band) in bands.iter().enumerate() {
        let last = k + 1 == bands.len();
        let shift = if k == 0 {
            0
        } else if last {
            width - (band.end - band.start)
        } else {
            1
        };
        let x = |column: u32| column - band.start + shift;
        // The band with the rung's rows, then without those it leaves empty.
        let mut part = RungLayout {
            columns: width,
            rows: laid.rows,
            cells: Vec::new(),
            wires: Vec::new(),
            label: None,
            connectors: Vec::new(),
        };
        for cell in laid
            .cells
            .iter()
            .filter(|c| band.start <= c.column && c.column < band.end)
        {
            let mut cell = cell.clone();
            cell.column = x(cell.column);
            part.cells.push(cell);
        }
        for wire in &laid.wires {
            match *wire {
                Wire::Horizontal { row, from, to } => {
                    let (from, to) = (from.max(band.start), to.min(band.end));
                    if from < to {
                        part.wires.push(Wire::Horizontal {
                            row,
                            from: x(from),
                            to: x(to),
                        });
                    }
                }
                Wire::Vertical { column, from, to } => {
                    if band.start <= column && column <= band.end {
                        part.wires.push(Wire::Vertical {
                            column: x(column),
                            from,
                            to,
                        });
                    }
                }
            }
        }
        for &(row, number) in &incoming {
            part.connectors.push(Connector {
                column: 0,
                row,
                number,
                outgoing: false,
            });
            if shift > 1 {
                part.wires.push(Wire::Horizontal {
                    row,
                    from: 1,
                    to: shift,
                });
            }
        }
        incoming.clear();
        if !last {
            for (left_row, right_row) in crossings(&laid, band.end) {
                part.connectors.push(Connector {
                    column: x(band.end),
                    row: left_row,
                    number: next_number,
                    outgoing: true,
                });
                incoming.push((right_row, next_number));
                next_number += 1;
            }
        }
        let rows = compact(&mut part);
        let top = out.rows;
        out.cells.extend(part.cells.into_iter().map(|mut c| {
            c.row += top;
            c
        }));
        out.wires.extend(part.wires.into_iter().map(|w| match w {
            Wire::Horizontal { row, from, to } => Wire::Horizontal {
                row: row + top,
                from,
                to,
            },
            Wire::Vertical { column, from, to } => Wire::Vertical {
                column,
                from: from + top,
                to: to + top,
            },
        }));
        out.connectors.extend(part.connectors.into_iter().map(|mut c| {
            c.row += top;
            c
        }));
        out.rows = top + rows;
    }
    out
}

/// Drops the rows of a band that nothing is on (a vertical wire only
/// passes through them); returns its height.
fn compact(part: &mut RungLayout) -> u32 {
    let mut used: Vec<u32> = part
        .cells
        .iter()
        .map(|c| c.row)
        .chain(part.connectors.iter().map(|c| c.row))
        .chain(part.wires.iter().flat_map(|w| match *w {
            Wire::Horizontal { row, .. } => vec![row],
            Wire::Vertical { from, to, .. } => vec![from, to],
        }))
        .collect();
    used.sort_unstable();
    used.dedup();
    let new = |row: u32| used.iter().position(|&r| r == row).map_or(row, |p| p as u32);
    for cell in &mut part.cells {
        cell.row = new(cell.row);
    }
    for connector in &mut part.connectors {
        connector.row = new(connector.row);
    }
    for wire in &mut part.wires {
        *wire = match *wire {
            Wire::Horizontal { row, from, to } => Wire::Horizontal {
                row: new(row),
                from,
                to,
            },
            Wire::Vertical { column, from, to } => Wire::Vertical {
                column,
                from: new(from),
                to: new(to),
            },
        };
    }
    (used.len() as u32).max(1)
}

/// Original columns `start..end` of one band.
struct Band {
    start: u32,
    end: u32,
}

/// Where to fold: each band as wide as it may be (the first and middle
/// bands give a column to the outgoing marks, every band after the first
/// one to the incoming marks), never through a cell, preferably not on a
/// vertical wire.
fn bands(laid: &RungLayout, width: u32) -> Vec<Band> {
    let mut bands = Vec::new();
    let mut start = 0;
    loop {
        let first = bands.is_empty();
        let room_if_last = if first { width } else { width - 1 };
        if laid.columns - start <= room_if_last {
            bands.push(Band {
                start,
                end: laid.columns,
            });
            return bands;
        }
        let room = if first { width - 1 } else { width - 2 };
        let straddles = |c: u32| {
            laid.cells
                .iter()
                .any(|cell| cell.column < c && c < cell.column + cell.width)
        };
        let vertical_at = |c: u32| {
            laid.wires
                .iter()
                .any(|w| matches!(*w, Wire::Vertical { column, .. } if column == c))
        };
        let candidates = (start + 1..=start + room).rev();
        let end = candidates
            .clone()
            .find(|&c| !straddles(c) && !vertical_at(c))
            .or_else(|| candidates.clone().find(|&c| !straddles(c)))
            // A cell wider than a band: the band ends after it.
            .unwrap_or_else(|| {
                laid.cells
                    .iter()
                    .filter(|cell| cell.column < start + room + 1 && start + room < cell.column + cell.width)
                    .map(|cell| cell.column + cell.width)
                    .max()
                    .unwrap_or(start + room)
            });
        bands.push(Band { start, end });
        start = end;
    }
}

/// The places a fold at column edge `c` cuts: for each node on the fold
/// (rows joined by a vertical wire on it) that has wiring on both sides,
/// the row its left side reaches the fold and the row its right side
/// leaves it.
fn crossings(laid: &RungLayout, c: u32) -> Vec<(u32, u32)> {
    let left = |row: u32| {
        laid.cells
            .iter()
            .any(|cell| cell.row == row && cell.column + cell.width == c)
            || laid
                .wires
                .iter()
                .any(|w| matches!(*w, Wire::Horizontal { row: r, from, to } if r == row && from < c && c <= to))
    };
    let right = |row: u32| {
        laid.cells.iter().any(|cell| cell.row == row && cell.column == c)
            || laid
                .wires
                .iter()
                .any(|w| matches!(*w, Wire::Horizontal { row: r, from, to } if r == row && from <= c && c < to))
    };
    // Each row's node: rows joined by verticals on the fold share one.
    let mut node: Vec<u32> = (0..laid.rows).collect();
    for wire in &laid.wires {
        if let Wire::Vertical { column, from, to } = *wire {
            if column == c {
                let joined = node[from as usize];
                for row in from..=to.min(laid.rows.saturating_sub(1)) {
                    let old = node[row as usize];
                    for n in node.iter_mut() {
                        if *n == old {
                            *n = joined;
                        }
                    }
                }
            }
        }
    }
    let mut out = Vec::new();
    let mut seen = Vec::new();
    for row in 0..laid.rows {
        let id = node[row as usize];
        if seen.contains(&id) {
            continue;
        }
        seen.push(id);
        let rows: Vec<u32> = (0..laid.rows).filter(|&r| node[r as usize] == id).collect();
        if let (Some(&l), Some(&r)) = (rows.iter().find(|&&r| left(r)), rows.iter().find(|&&r| right(r))) {
            out.push((l, r));
        }
    }
    out
}
