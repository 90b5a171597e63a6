//! Per-frame entities that draw the same welded mesh with the same `StandardMaterial` (a crowd
//! spawned from one glTF) share one [`TessellaMaterial`] and one evaluated buffer, each entity
//! a slot of it that its child's `MeshTag` names. Bevy batches the draws of one mesh and one
//! material into one instanced draw a pass; a material per entity would cost a draw and a
//! bind group per entity and pass (at 100 creatures, level 4, the offline-refined crowd with a
//! material each cost 1.13x the one with a shared material).

use crate::material::TessellaMaterial;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::render::storage::ShaderBuffer;

/// Floats a vertex of a pool's buffer holds: position then normal.
pub const EVALUATED_FLOATS: usize = 6;

/// Bytes a pool's buffer may hold: the storage binding size every WebGPU device accepts
/// (128 MiB). A pool that cannot grow more opens another page.
pub(crate) const POOL_BYTES: u64 = 128 << 20;

/// Slots start at multiples of this many bytes: the largest storage-offset alignment WebGPU
/// allows, so the compute pass can bind each slot at its offset.
const SLOT_ALIGN: u64 = 256;

/// A pool: the welded mesh and base material its entities share, and which page of them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct PoolKey {
    pub mesh: AssetId<Mesh>,
    pub material: AssetId<StandardMaterial>,
    pub page: u32,
}

/// One pool: the shared material and buffer, and which entity holds which slot.
pub(crate) struct Pool {
    pub material: Handle<TessellaMaterial>,
    pub buffer: Handle<ShaderBuffer>,
    /// Vertices from one slot's start to the next: the welded vertices rounded up so a
    /// slot starts at a multiple of [`SLOT_ALIGN`] bytes.
    pub stride: u32,
    capacity: u32,
    /// Slots given out so far; freed ones below it are in `free`.
    next: u32,
    free: Vec<u32>,
    members: HashMap<Entity, u32>,
}

impl Pool {
    /// Bytes of one slot.
    fn slot_bytes(&self) -> u64 {
        u64::from(self.stride) * (EVALUATED_FLOATS * 4) as u64
    }

    /// The most slots a page holds.
    fn max_slots(&self) -> u32 {
        (POOL_BYTES / self.slot_bytes()).clamp(1, u64::from(u32::MAX)) as u32
    }

    /// The byte offset of `slot` in the buffer.
    pub fn offset(&self, slot: u32) -> u64 {
        u64::from(slot) * self.slot_bytes()
    }

    fn has_room(&self) -> bool {
        !self.free.is_empty() || self.next < self.max_slots()
    }
}

/// Every pool of the app, kept by the main world and read by the render world's extraction.
#[derive(Resource, Default)]
pub(crate) struct Pools(pub HashMap<PoolKey, Pool>);

/// Where an entity's vertices go: its pool and slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Seat {
    pub pool: PoolKey,
    pub slot: u32,
}

impl Pools {
    /// A slot for `entity`, which draws `vertices` welded vertices of `mesh` with `base`: its
    /// slot already, else a free one of a page of that mesh and base, else a new slot (the
    /// page's buffer doubled, the material rebound to it; every member evaluates again, as
    /// its buffer changed), else a new page, whose material `make` makes around its buffer.
    #[allow(clippy::too_many_arguments)]
    pub fn join(
        &mut self,
        entity: Entity,
        mesh: AssetId<Mesh>,
        base: AssetId<StandardMaterial>,
        vertices: u32,
        buffers: &mut Assets<ShaderBuffer>,
        materials: &mut Assets<TessellaMaterial>,
        make: impl FnOnce(Handle<ShaderBuffer>) -> TessellaMaterial,
    ) -> Seat {
        let same = |k: &PoolKey| k.mesh == mesh && k.material == base;
        let sitting = self
            .0
            .iter()
            .find(|(k, p)| same(k) && p.members.contains_key(&entity));
        if let Some((key, pool)) = sitting {
            return Seat {
                pool: *key,
                slot: pool.members[&entity],
            };
        }
        let open = self
            .0
            .iter()
            .filter(|(k, p)| same(k) && p.has_room())
            .map(|(k, _)| *k)
            .min_by_key(|k| k.page);
        let key = match open {
            Some(k) => k,
            None => {
                let page = (0..)
                    .find(|&page| {
                        !self.0.contains_key(&PoolKey {
                            mesh,
                            material: base,
                            page,
                        })
                    })
                    .unwrap_or(0);
                let key = PoolKey {
                    mesh,
                    material: base,
                    page,
                };
                let stride = stride(vertices);
                let buffer = buffers.add(slots_buffer(stride, 1));
                let material = materials.add(make(buffer.clone()));
                let pool = Pool {
                    material,
                    buffer,
                    stride,
                    capacity: 1,
                    next: 0,
                    free: Vec::new(),
                    members: HashMap::new(),
                };
                self.0.insert(key, pool);
                key
            }
        };
        let Some(pool) = self.0.get_mut(&key) else {
            unreachable!("the pool was found or made above");
        };
        let slot = match pool.free.pop() {
            Some(s) => s,
            None => {
                if pool.next == pool.capacity {
                    // Doubled, up to the page's most: the old slots' contents are not kept
                    // (each member evaluates into its new buffer this frame).
                    pool.capacity = (pool.capacity * 2).min(pool.max_slots());
                    pool.buffer = buffers.add(slots_buffer(pool.stride, pool.capacity));
                    if let Some(mut m) = materials.get_mut(&pool.material) {
                        m.extension.evaluated = pool.buffer.clone();
                    }
                }
                pool.next += 1;
                pool.next - 1
            }
        };
        pool.members.insert(entity, slot);
        Seat { pool: key, slot }
    }

    /// Frees the slots of entities that no longer sit where the pool has them (despawned,
    /// untessellated, drawn otherwise or moved to another pool: `seated` says where each
    /// sits now), and drops pools left empty (their material and buffer go with them).
    pub fn release(&mut self, seated: impl Fn(Entity) -> Option<Seat>) {
        for (key, pool) in self.0.iter_mut() {
            let gone: Vec<(Entity, u32)> = pool
                .members
                .iter()
                .filter(|(e, s)| {
                    seated(**e)
                        != Some(Seat {
                            pool: *key,
                            slot: **s,
                        })
                })
                .map(|(e, s)| (*e, *s))
                .collect();
            for (entity, slot) in gone {
                pool.members.remove(&entity);
                pool.free.push(slot);
            }
        }
        self.0.retain(|_, pool| !pool.members.is_empty());
    }
}

/// Vertices a slot spans: `vertices` rounded up to whole [`SLOT_ALIGN`] byte units.
fn stride(vertices: u32) -> u32 {
    // 24 bytes a vertex: 32 vertices are 3 x 256 bytes, the least whole number of units.
    const UNIT: u32 = 32;
    const _: () = assert!((UNIT as u64 * EVALUATED_FLOATS as u64 * 4).is_multiple_of(SLOT_ALIGN));
    vertices.max(1).div_ceil(UNIT) * UNIT
}

/// A pool buffer of `slots` slots of `stride` vertices, written by the compute pass alone.
fn slots_buffer(stride: u32, slots: u32) -> ShaderBuffer {
    let bytes = u64::from(stride) * u64::from(slots) * (EVALUATED_FLOATS * 4) as u64;
    ShaderBuffer::with_size(bytes, bevy::asset::RenderAssetUsages::RENDER_WORLD)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pools with their assets, as the `tessellate` system holds them.
    #[derive(Default)]
    struct Fixture {
        pools: Pools,
        buffers: Assets<ShaderBuffer>,
        materials: Assets<TessellaMaterial>,
    }

    impl Fixture {
        fn join(&mut self, entity: u32, mesh: u128, base: u128, vertices: u32) -> Seat {
            let entity = Entity::from_raw_u32(entity).unwrap();
            let mesh = AssetId::<Mesh>::Uuid {
                uuid: bevy::asset::uuid::Uuid::from_u128(mesh),
            };
            let base = AssetId::<StandardMaterial>::Uuid {
                uuid: bevy::asset::uuid::Uuid::from_u128(base),
            };
            let make = |b: Handle<ShaderBuffer>| TessellaMaterial {
                base: StandardMaterial::default(),
                extension: crate::material::TessellaExtension {
                    stencil: b.clone(),
                    net_points: b.clone(),
                    net_normals: b.clone(),
                    eval_params: b.clone(),
                    displace_params: b.clone(),
                    displace_data: b.clone(),
                    edge_table: b.clone(),
                    face_uvs: b.clone(),
                    evaluated: b,
                    normal_mode: Default::default(),
                    per_frame: true,
                },
            };
            let (buffers, materials) = (&mut self.buffers, &mut self.materials);
            self.pools
                .join(entity, mesh, base, vertices, buffers, materials, make)
        }
    }

    /// Slots start at 256-byte multiples; a crowd of one mesh and material fills one page
    /// whose buffer doubles (the material rebound to the new one), with distinct slots; a
    /// re-join keeps the slot; a freed slot is given again; another base material gets its
    /// own pool; a page full at 128 MiB opens a second; empty pools go.
    #[test]
    fn crowds_share_pages_of_slots() {
        assert_eq!(stride(1), 32);
        assert_eq!(stride(32), 32);
        assert_eq!(stride(33), 64);
        assert_eq!((u64::from(stride(1000)) * 24) % SLOT_ALIGN, 0);

        let mut f = Fixture::default();
        let seats: Vec<Seat> = (1..=5).map(|e| f.join(e, 1, 1, 1000)).collect();
        assert_eq!(f.pools.0.len(), 1);
        assert_eq!(f.materials.len(), 1);
        let slots: Vec<u32> = seats.iter().map(|s| s.slot).collect();
        assert_eq!(slots, vec![0, 1, 2, 3, 4]);
        let pool = &f.pools.0[&seats[0].pool];
        assert_eq!(pool.capacity, 8);
        let bound = &f.materials.iter().next().unwrap().1.extension.evaluated;
        assert_eq!(bound, &pool.buffer);
        let size = match f.buffers.get(&pool.buffer).unwrap().data {
            bevy::render::storage::ShaderBufferData::Uninitialized(size) => size,
            _ => panic!("a pool buffer with data"),
        };
        assert_eq!(size, 8 * pool.slot_bytes());
        assert_eq!(pool.offset(3), 3 * 1024 * 24);
        // The same entity again: the same slot.
        assert_eq!(f.join(3, 1, 1, 1000), seats[2]);
        // Entity 2 leaves: its slot goes to the next comer.
        f.pools.release(|e| {
            let i = e.index_u32() as usize;
            (i != 2).then(|| seats[i - 1])
        });
        let seat = f.join(9, 1, 1, 1000);
        assert_eq!(seat.slot, 1);
        // Another base material: a pool of its own.
        let own = f.join(9, 1, 2, 1000);
        assert_ne!(own.pool, seat.pool);
        assert_eq!(f.materials.len(), 2);
        // Slots of 4 Mi vertices (96 MiB): one a page.
        let (a, b) = (f.join(1, 3, 1, 1 << 22), f.join(2, 3, 1, 1 << 22));
        assert_eq!((a.pool.page, b.pool.page, a.slot, b.slot), (0, 1, 0, 0));
        // Nobody sits anywhere: every pool goes.
        f.pools.release(|_| None);
        assert!(f.pools.0.is_empty());
    }
}
