//! GNOME's thumbnailer sandbox, reproduced: the bubblewrap arguments of `add_bwrap` and the
//! seccomp filter of `setup_seccomp` in libgnome-desktop/gnome-desktop-thumbnail-script.c
//! (gnome-desktop at commit 6f0dc0f6b7ebf20e51b3507d7e35bf063ad56bc7, August 2026), for a
//! 64-bit x86 machine (`flatpak_get_arch` = "x86_64", multiarch and devel off, as
//! `script_exec_new`'s caller passes them; personality PER_LINUX).

use std::ffi::OsString;
use std::os::unix::fs::MetadataExt as _;
use std::path::{Path, PathBuf};

/// Where GNOME binds the input: `/tmp/gnome-desktop-file-to-thumbnail.<ext>`.
pub fn sandbox_input(ext: &str) -> String {
    format!("/tmp/gnome-desktop-file-to-thumbnail.{ext}")
}

/// Where GNOME's thumbnailer writes inside the sandbox: `/tmp` is the output folder.
pub const SANDBOX_OUTPUT: &str = "/tmp/gnome-desktop-thumbnailer.png";

/// `add_bwrap`'s arguments (after the program name `bwrap`), in its order, for the input
/// `infile` (host path) bound at `s_infile`, the output folder `outdir` (bound as /tmp) and
/// the GStreamer cache folder `gst_cache_dir` (GNOME's is
/// `~/.cache/gnome-desktop-thumbnailer/gstreamer-1.0`; the test gives a folder of its own so
/// as not to write in the user's home).
pub fn add_bwrap(
    infile: &Path,
    s_infile: &str,
    outdir: &Path,
    gst_cache_dir: &Path,
) -> Vec<OsString> {
    let mut a: Vec<OsString> = Vec::new();
    let mut add = |args: &[&dyn AsRef<std::ffi::OsStr>]| {
        a.extend(args.iter().map(|s| s.as_ref().to_os_string()));
    };
    add(&[&"--ro-bind", &"/usr", &"/usr"]);
    add(&[&"--ro-bind-try", &"/etc/ld.so.cache", &"/etc/ld.so.cache"]);
    // "These directories might be symlinks into /usr/..."
    for dir in ["bin", "lib64", "lib", "sbin"] {
        let absolute_dir = format!("/{dir}");
        if !Path::new(&absolute_dir).exists() {
            continue;
        }
        if path_is_usrmerged(&absolute_dir) {
            // g_strdup_printf ("/usr/%s", absolute_dir): "/usr//bin", as upstream has it.
            let symlink_target = format!("/usr/{absolute_dir}");
            add(&[&"--symlink", &symlink_target, &absolute_dir]);
        } else {
            add(&[&"--ro-bind", &absolute_dir, &absolute_dir]);
        }
    }
    // FONTCONFIG_CACHE_PATH, a build-time setting: Debian's and Fedora's is
    // /var/cache/fontconfig (not under /usr, so it is bound).
    add(&[
        &"--ro-bind-try",
        &"/var/cache/fontconfig",
        &"/var/cache/fontconfig",
    ]);
    let registry = gst_cache_dir.join("gstreamer-1.0.registry");
    add(&[
        &"--setenv",
        &"GST_REGISTRY_1_0",
        &registry,
        &"--bind",
        &gst_cache_dir,
        &gst_cache_dir,
    ]);
    add(&[&"--ro-bind-try", &"/etc/alternatives", &"/etc/alternatives"]);
    add(&[
        &"--proc",
        &"/proc",
        &"--dev",
        &"/dev",
        &"--chdir",
        &"/",
        &"--setenv",
        &"GIO_USE_VFS",
        &"local",
        &"--unshare-all",
        &"--die-with-parent",
    ]);
    // G_MESSAGES_DEBUG, G_MESSAGES_PREFIXED and GST_DEBUG are passed only when set; the
    // test's caller does not set them. INSTALL_PREFIX is /usr: nothing more.
    add(&[&"--bind", &outdir, &"/tmp"]);
    add(&[&"--ro-bind", &infile, &s_infile]);
    a
}

/// `path_is_usrmerged`: /dir and /usr/dir are the same directory (`g_stat` follows links).
fn path_is_usrmerged(dir: &str) -> bool {
    let (Ok(src), Ok(target)) = (
        std::fs::metadata(dir),
        std::fs::metadata(format!("/usr/{dir}")),
    ) else {
        return false;
    };
    src.dev() == target.dev() && src.ino() == target.ino()
}

/// `setup_seccomp`'s filter as a classic BPF program (the bytes libseccomp's
/// `seccomp_export_bpf` writes: 8 bytes per instruction, native byte order), for x86-64;
/// `None` on other machines (the test then runs without it and says so).
///
/// Default action allow; a foreign architecture (and the x32 syscall range) is killed, as
/// libseccomp does for an architecture the filter was not made for. Blocked:
/// - with EPERM: syslog, uselib, acct, quotactl, add_key, keyctl, request_key, move_pages,
///   mbind, get_mempolicy, set_mempolicy, migrate_pages, unshare, setns, mount, umount2
///   (x86-64 has no umount), pivot_root, chroot, clone with CLONE_NEWUSER in its flags,
///   ioctl TIOCSTI and TIOCLINUX, modify_ldt (multiarch off), and the "non-devel" list:
///   perf_event_open, personality other than PER_LINUX, ptrace;
/// - with ENOSYS: clone3, open_tree, move_mount, fsopen, fsconfig, fsmount, fspick,
///   mount_setattr;
/// - with EAFNOSUPPORT: socket of any family but AF_UNSPEC, AF_LOCAL, AF_INET, AF_INET6 and
///   AF_NETLINK.
pub fn seccomp_bpf() -> Option<Vec<u8>> {
    if !cfg!(all(target_arch = "x86_64", target_os = "linux")) {
        return None;
    }
    const AUDIT_ARCH_X86_64: u32 = 0xC000_003E;
    const X32_SYSCALL_BIT: u32 = 0x4000_0000;
    const KILL: u32 = 0; // SECCOMP_RET_KILL_THREAD, libseccomp's default bad-arch action
    const ALLOW: u32 = 0x7fff_0000;
    const fn errno(e: u32) -> u32 {
        0x0005_0000 | e
    }
    const EPERM: u32 = 1;
    const ENOSYS: u32 = 38;
    const EAFNOSUPPORT: u32 = 97;
    // struct seccomp_data: nr at 0, arch at 4, args[i] at 16 + 8 i (low word first).
    const NR: u32 = 0;
    const ARCH: u32 = 4;
    const fn arg_lo(i: u32) -> u32 {
        16 + 8 * i
    }
    const fn arg_hi(i: u32) -> u32 {
        20 + 8 * i
    }
    // BPF opcodes.
    const LD_ABS: u16 = 0x20; // BPF_LD | BPF_W | BPF_ABS
    const JEQ: u16 = 0x15; // BPF_JMP | BPF_JEQ | BPF_K
    const JGE: u16 = 0x35; // BPF_JMP | BPF_JGE | BPF_K
    const JSET: u16 = 0x45; // BPF_JMP | BPF_JSET | BPF_K
    const RET: u16 = 0x06; // BPF_RET | BPF_K

    let mut p: Vec<(u16, u8, u8, u32)> = Vec::new();
    let ld = |at: u32| (LD_ABS, 0u8, 0u8, at);
    let ret = |k: u32| (RET, 0u8, 0u8, k);
    p.push(ld(ARCH));
    p.push((JEQ, 1, 0, AUDIT_ARCH_X86_64));
    p.push(ret(KILL));
    p.push(ld(NR));
    p.push((JGE, 0, 1, X32_SYSCALL_BIT));
    p.push(ret(KILL));
    let simple: [(u32, u32); 29] = [
        (103, EPERM),  // syslog
        (134, EPERM),  // uselib
        (163, EPERM),  // acct
        (179, EPERM),  // quotactl
        (248, EPERM),  // add_key
        (250, EPERM),  // keyctl
        (249, EPERM),  // request_key
        (279, EPERM),  // move_pages
        (237, EPERM),  // mbind
        (239, EPERM),  // get_mempolicy
        (238, EPERM),  // set_mempolicy
        (256, EPERM),  // migrate_pages
        (272, EPERM),  // unshare
        (308, EPERM),  // setns
        (165, EPERM),  // mount
        (166, EPERM),  // umount2
        (155, EPERM),  // pivot_root
        (161, EPERM),  // chroot
        (435, ENOSYS), // clone3
        (428, ENOSYS), // open_tree
        (429, ENOSYS), // move_mount
        (430, ENOSYS), // fsopen
        (431, ENOSYS), // fsconfig
        (432, ENOSYS), // fsmount
        (433, ENOSYS), // fspick
        (442, ENOSYS), // mount_setattr
        (154, EPERM),  // modify_ldt (multiarch off)
        (298, EPERM),  // perf_event_open (devel off)
        (101, EPERM),  // ptrace (devel off)
    ];
    for (nr, e) in simple {
        p.push((JEQ, 0, 1, nr));
        p.push(ret(errno(e)));
    }
    // clone (56): flags (arg 0) & CLONE_NEWUSER == CLONE_NEWUSER.
    p.push((JEQ, 0, 4, 56));
    p.push(ld(arg_lo(0)));
    p.push((JSET, 0, 1, 0x1000_0000));
    p.push(ret(errno(EPERM)));
    p.push(ld(NR));
    // ioctl (16): request (arg 1) & 0xFFFFFFFF is TIOCSTI or TIOCLINUX.
    p.push((JEQ, 0, 5, 16));
    p.push(ld(arg_lo(1)));
    p.push((JEQ, 1, 0, 0x5412)); // TIOCSTI
    p.push((JEQ, 0, 1, 0x541C)); // TIOCLINUX
    p.push(ret(errno(EPERM)));
    p.push(ld(NR));
    // personality (135): arg 0 != PER_LINUX (0), compared on 64 bits.
    p.push((JEQ, 0, 6, 135));
    p.push(ld(arg_lo(0)));
    p.push((JEQ, 0, 2, 0));
    p.push(ld(arg_hi(0)));
    p.push((JEQ, 1, 0, 0));
    p.push(ret(errno(EPERM)));
    p.push(ld(NR));
    // socket (41): families 0, 1, 2, 10 and 16 pass; the others in between and every
    // family from 17 on (a high word set is such a family) get EAFNOSUPPORT.
    p.push((JEQ, 0, 9, 41));
    p.push(ld(arg_hi(0)));
    p.push((JEQ, 0, 6, 0));
    p.push(ld(arg_lo(0)));
    for (i, family) in [0u32, 1, 2, 10, 16].into_iter().enumerate() {
        // A match jumps over the remaining tests and the return, to the reload.
        p.push((JEQ, (5 - i) as u8, 0, family));
    }
    p.push(ret(errno(EAFNOSUPPORT)));
    p.push(ld(NR));
    p.push(ret(ALLOW));
    let mut bytes = Vec::with_capacity(p.len() * 8);
    for (code, jt, jf, k) in p {
        bytes.extend_from_slice(&code.to_ne_bytes());
        bytes.push(jt);
        bytes.push(jf);
        bytes.extend_from_slice(&k.to_ne_bytes());
    }
    Some(bytes)
}

/// `bwrap` on the PATH, if any.
pub fn find_bwrap() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join("bwrap"))
        .find(|p| p.is_file())
}
