//! The cost table (rtl/synth/costs.toml) and the device model
//! (harness/output/device.rs): the committed table reads, says where every figure
//! comes from, and refuses what it does not hold; a device's fill is the
//! binding resource's quotient, and its frames a second follow.

use golden::fp::Method;
use rtcosim::design::processor::ProcessorKind;
use rtcosim::output::device::{Build, CostError, CostTable, Device, Source};

fn build(processor: ProcessorKind, exposure: bool) -> Build {
    Build {
        processor,
        recip: Method::Exact,
        sqrt: Method::Exact,
        stack_depth: 8,
        exposure,
        refraction: false,
    }
}

/// One entry of a table, as TOML, with `extra` lines added.
fn entry(processor: &str, exposure: bool, extra: &str) -> String {
    format!(
        "[[build]]\nprocessor = \"{processor}\"\nrecip = \"exact\"\nsqrt = \"exact\"\n\
         stack_depth = 8\nexposure = {exposure}\nrefraction = false\nluts = 10000\nlut_memory = 1500\n\
         flip_flops = 7000\ndsp48e1 = 24\nbram36 = 21\nfmax_mhz = 100.0\n{extra}\
         source.measured = \"rtl/synth/synth.sh xc6v fast-pp exact\"\n"
    )
}

fn table(entries: &str) -> Result<CostTable, CostError> {
    CostTable::parse(&format!(
        "yosys = \"Yosys 0.23\"\nnextpnr = \"nextpnr-ecp5 0.11.1\"\n{entries}"
    ))
}

#[test]
fn the_committed_table_reads_and_says_where_each_figure_comes_from() {
    let t = CostTable::builtin().unwrap_or_else(|e| panic!("{e}"));
    assert!(t.yosys.starts_with("Yosys "), "{}", t.yosys);
    assert!(!t.costs.is_empty());
    for c in &t.costs {
        match &c.source {
            Source::Measured(command) => assert!(
                command.starts_with("rtl/synth/synth.sh xc6v "),
                "{}: {command}",
                c.build
            ),
            Source::Interpolated(how) => assert!(!how.is_empty(), "{}", c.build),
        }
        assert_eq!(t.cost(c.build), Ok(c));
    }
    // The compact processor as docs/rtl.md measures it, without
    // refraction and with.
    let compact = t
        .cost(build(ProcessorKind::Compact, true))
        .expect("measured");
    assert_eq!((compact.luts, compact.dsp48e1), (13_545, 80));
    let compact = t
        .cost(Build {
            refraction: true,
            ..build(ProcessorKind::Compact, true)
        })
        .expect("measured");
    assert_eq!((compact.luts, compact.dsp48e1), (14_635, 80));
}

/// 24 DSPs and 21 block RAMs a processor: 36 by DSP (864 / 24), 34 by
/// block RAM (720 / 21 = 34.3): block RAM binds; at 100 MHz, a frame of
/// 59,364,805 cycles on one processor is 34 x 100e6 / 59,364,805 = 57.27
/// frames a second split evenly.
#[test]
fn a_device_fills_to_its_binding_resource() {
    let t = table(&entry("fast", true, "")).unwrap_or_else(|e| panic!("{e}"));
    let cost = t.cost(build(ProcessorKind::Fast, true)).expect("the entry");
    let filled = Device::LX760.fill(cost);
    assert_eq!((filled.processors, filled.binding), (34, "block RAM"));
    let fps = filled.frames_per_second(59_364_805);
    assert!((fps - 57.27).abs() < 0.01, "{fps}");

    // Half the block RAM: DSPs bind at 36.
    let t = table(&entry("fast", true, "").replace("bram36 = 21", "bram36 = 10.5"))
        .unwrap_or_else(|e| panic!("{e}"));
    let filled = Device::LX760.fill(&t.costs[0]);
    assert_eq!((filled.processors, filled.binding), (36, "DSP48E1"));
}

#[test]
fn a_bad_or_incomplete_table_is_refused_naming_the_build() {
    let missing = build(ProcessorKind::Fast, false);
    let t = table(&entry("fast", true, "")).unwrap_or_else(|e| panic!("{e}"));
    let e = t.cost(missing).unwrap_err();
    assert_eq!(e, CostError::Missing(missing));
    assert!(
        e.to_string().contains(
            "no cost for the fast processor, recip exact, sqrt exact, \
             STACK_DEPTH 8, without the exponential"
        ),
        "{e}"
    );

    let twice = format!("{}{}", entry("fast", true, ""), entry("fast", true, ""));
    assert!(matches!(table(&twice), Err(CostError::Duplicate(_))));
    let e = table(&entry("compact", false, "")).unwrap_err();
    assert!(e.to_string().contains("always has its exponential"), "{e}");
    let e =
        table(&entry("fast", true, "").replace("fmax_mhz = 100.0", "fmax_mhz = -1.0")).unwrap_err();
    assert!(e.to_string().contains("clocks must be positive"), "{e}");
    let e = table(&entry("fast", true, "").replace("recip = \"exact\"", "recip = \"quick\""))
        .unwrap_err();
    assert!(
        e.to_string()
            .contains("method 'quick' is neither exact nor fast"),
        "{e}"
    );
    let e = table(&entry("fast", true, "colour = 1\n")).unwrap_err();
    assert!(e.to_string().contains("colour"), "{e}");
}

/// Every build the sweep's grid needs is priced (each processor, each
/// method pair, with the exponential), and each interpolated mixed pair
/// follows the table's stated rule: per resource the larger of its
/// processor's measured exact and fast pairs, the lower of their clocks.
#[test]
fn the_table_prices_every_swept_build_and_interpolates_by_its_rule() {
    let t = CostTable::builtin().unwrap_or_else(|e| panic!("{e}"));
    for processor in [ProcessorKind::Compact, ProcessorKind::Fast] {
        let pair = |recip, sqrt| {
            t.cost(Build {
                recip,
                sqrt,
                ..build(processor, true)
            })
            .unwrap_or_else(|e| panic!("{e}"))
        };
        let (exact, fast) = (
            pair(Method::Exact, Method::Exact),
            pair(Method::Fast, Method::Fast),
        );
        for (recip, sqrt) in [(Method::Exact, Method::Fast), (Method::Fast, Method::Exact)] {
            let mixed = pair(recip, sqrt);
            if let Source::Interpolated(_) = mixed.source {
                assert_eq!(mixed.luts, exact.luts.max(fast.luts), "{}", mixed.build);
                assert_eq!(mixed.lut_memory, exact.lut_memory.max(fast.lut_memory));
                assert_eq!(mixed.flip_flops, exact.flip_flops.max(fast.flip_flops));
                assert_eq!(mixed.dsp48e1, exact.dsp48e1.max(fast.dsp48e1));
                assert_eq!(mixed.bram36, exact.bram36.max(fast.bram36));
                assert_eq!(mixed.fmax_mhz, exact.fmax_mhz.min(fast.fmax_mhz));
            }
        }
    }
    // With refraction every pair is priced: an interpolated entry is its
    // pair's entry without refraction plus the exact pair's increment,
    // resource by resource, at the lower of the two clocks.
    for processor in [ProcessorKind::Compact, ProcessorKind::Fast] {
        let exact = |refraction| {
            t.cost(Build {
                refraction,
                ..build(processor, true)
            })
            .unwrap_or_else(|e| panic!("{e}"))
        };
        let (off, on) = (exact(false), exact(true));
        assert!(matches!(on.source, Source::Measured(_)), "{}", on.build);
        let step = |a: u32, b: u32, base: u32| i64::from(base) + i64::from(b) - i64::from(a);
        for recip in Method::ALL {
            for sqrt in Method::ALL {
                let with = Build {
                    recip,
                    sqrt,
                    refraction: true,
                    ..build(processor, true)
                };
                let c = t.cost(with).unwrap_or_else(|e| panic!("{e}"));
                if let Source::Interpolated(_) = c.source {
                    let base = t
                        .cost(Build {
                            refraction: false,
                            ..with
                        })
                        .unwrap_or_else(|e| panic!("{e}"));
                    assert_eq!(
                        i64::from(c.luts),
                        step(off.luts, on.luts, base.luts),
                        "{with}"
                    );
                    assert_eq!(
                        i64::from(c.lut_memory),
                        step(off.lut_memory, on.lut_memory, base.lut_memory)
                    );
                    assert_eq!(
                        i64::from(c.flip_flops),
                        step(off.flip_flops, on.flip_flops, base.flip_flops)
                    );
                    assert_eq!(
                        i64::from(c.dsp48e1),
                        step(off.dsp48e1, on.dsp48e1, base.dsp48e1)
                    );
                    assert_eq!(c.bram36, base.bram36 + on.bram36 - off.bram36);
                    assert_eq!(c.fmax_mhz, base.fmax_mhz.min(on.fmax_mhz));
                }
            }
        }
    }
    // Without exposure the fast processor's exact pair has its own build;
    // the others fall back to the build with the exponential.
    let noexp = t
        .build_for(build(ProcessorKind::Fast, false))
        .expect("priced");
    assert!(!noexp.build.exposure);
    let fallback = t
        .build_for(Build {
            recip: Method::Fast,
            sqrt: Method::Fast,
            ..build(ProcessorKind::Fast, false)
        })
        .expect("priced");
    assert!(fallback.build.exposure);
}
