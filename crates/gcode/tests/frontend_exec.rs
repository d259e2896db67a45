//! Control flow and parameter semantics of the executor, each case checked against the
//! output of LinuxCNC's `rs274 -g` on the same program (figures noted per case).

use oficina_gcode::Params;
use oficina_gcode::{Block, Note};
use oficina_gcode::{Diagnostic, Dialect};
use oficina_gcode::{Executor, Limits, ProgramEnd};

/// Every block and every error, in order, with a bound on the number of steps; stops after
/// M2/M30 as the interpreter does.
fn run(text: &str) -> (Vec<Block>, Vec<Diagnostic>) {
    let mut exec = Executor::from_text(text, Dialect::LinuxCnc);
    exec.set_limits(Limits {
        max_call_depth: 10,
        max_loop_iterations: 10_000,
        max_idle_iterations: 1_000,
        max_total_jumps: 50_000,
    });
    let mut params = Params::new();
    let (mut blocks, mut errors) = (Vec::new(), Vec::new());
    for _ in 0..100_000 {
        match exec.next_block(&mut params) {
            Some(Ok(b)) => {
                let end = b.words_of('M').any(|w| w.value == 2.0 || w.value == 30.0);
                blocks.push(b);
                if end {
                    return (blocks, errors);
                }
            }
            Some(Err(e)) => errors.push(e),
            None => return (blocks, errors),
        }
    }
    panic!("the executor did not finish within 100000 steps");
}

/// The X values of the blocks that have one (what rs274 shows as STRAIGHT_TRAVERSE x).
fn xs(text: &str) -> Vec<f64> {
    let (blocks, errors) = run(text);
    assert!(errors.is_empty(), "unexpected errors: {errors:?}");
    blocks.iter().filter_map(|b| b.get('X')).collect()
}

fn first_error(text: &str) -> Diagnostic {
    let (_, errors) = run(text);
    errors.into_iter().next().expect("an error")
}

#[test]
fn values_on_a_line_are_read_before_its_assignments() {
    // rs274: X8 Y0, then X0 Y2
    assert_eq!(
        xs("#1=[2**3]\n#2=#1 #1=5 G0 X#1 Y#2\nG0 X#2"),
        vec![8.0, 8.0]
    );
    let (blocks, _) = run("#1=2 G0 X#1\nG0 Y#1");
    assert_eq!(blocks[0].get('X'), Some(0.0));
    assert_eq!(blocks[1].get('Y'), Some(2.0));
    assert_eq!(blocks[0].assignments.len(), 1);
    // rs274: the last assignment of the same parameter wins: X3.
    assert_eq!(xs("#1=2 #1=3\nG0 X#1"), vec![3.0]);
}

#[test]
fn a_named_parameter_assigned_on_a_line_reads_as_zero_later_on_it() {
    // rs274: "#<a>=5 G0 X#<a>" gives X0; reading it before its assignment is an error.
    assert_eq!(xs("#<a>=5 G0 X#<a>\nG0 X#<a>"), vec![0.0, 5.0]);
    assert!(first_error("G0 X#<a> #<a>=5").message.contains("#<a>"));
    // rs274: "#<a>=1", "#<a>=2 #<b>=#<a>", "G0 X#<b>" gives X1.
    assert_eq!(xs("#<a>=1\n#<a>=2 #<b>=#<a>\nG0 X#<b>"), vec![1.0]);
    // Names ignore case and blanks: rs274 gives X2.
    assert_eq!(xs("#<A b>=2\nG0 X#<ab>"), vec![2.0]);
}

#[test]
fn indirect_and_out_of_range_parameters() {
    assert_eq!(xs("#1=2\n#2=7\nG0 X##1"), vec![7.0]);
    assert!(first_error("G0 X#5602").message.contains("out of range"));
    assert!(first_error("#0=1").message.contains("out of range"));
    assert!(first_error("#1=1.00011\nG0 X##1")
        .message
        .contains("not an integer"));
    // rs274 accepts #5601.
    assert_eq!(xs("#5601=4\nG0 X#5601"), vec![4.0]);
}

#[test]
fn subroutines_with_arguments_and_return_values() {
    // rs274: X3 Y4, X30, X25
    let p = "o100 sub\n G0 X#1 Y#2\n o100 return [#1*10]\no100 endsub\no<sq> sub\no<sq> endsub [#1*#1]\n\
             o100 call [3] [4]\nG0 X#<_value>\no<SQ> call [5]\nG0 X#<_value>\nM2";
    assert_eq!(xs(p), vec![3.0, 30.0, 25.0]);
    // Arguments are local: the caller's #1 comes back (rs274: X9 after the call).
    assert_eq!(
        xs("o1 sub\nG0 X#1\no1 endsub\n#1=9\no1 call [1]\nG0 X#1"),
        vec![1.0, 9.0]
    );
    // No return value: _value is 0 (rs274).
    assert_eq!(
        xs("o1 sub\no1 return [5]\no1 endsub\no1 call\no2 sub\no2 endsub\no2 call\nG0 X#<_value>"),
        vec![0.0]
    );
    // o0100 and o100 are one label (rs274: X1).
    assert_eq!(xs("o0100 sub\nG0 X1\no100 endsub\no100 call"), vec![1.0]);
}

#[test]
fn forward_calls_find_the_definition_below() {
    // rs274: X3 then X30; the subroutine sits after M2.
    let p = "o100 call [3] [4]\nG0 X#<_value>\nM2\no100 sub\n  G0 X#1 Y#2\n  o100 return [#1*10]\no100 endsub";
    assert_eq!(xs(p), vec![3.0, 30.0]);
    // rs274: reaching the definition of a sub called before it was defined is an error
    // ("found in illegal location"), reported at the definition.
    let e = first_error("o100 call [3]\no100 sub\nG0 X#1\no100 endsub\nG0 X99");
    assert_eq!(e.span.line, 2);
    // After that error the body is skipped and the program goes on.
    let (blocks, _) = run("o100 call [3]\no100 sub\nG0 X#1\no100 endsub\nG0 X99");
    assert_eq!(
        blocks.iter().filter_map(|b| b.get('X')).collect::<Vec<_>>(),
        vec![3.0, 99.0]
    );
}

#[test]
fn subroutine_errors() {
    assert!(first_error("o9 call").message.contains("o9 is not defined"));
    assert!(first_error("o1 return")
        .message
        .contains("outside a subroutine"));
    assert!(first_error("o1 sub\no1 endsub\no1 sub\no1 endsub")
        .message
        .contains("defined twice"));
    assert!(first_error("o1 sub\no2 sub\no2 endsub\no1 endsub")
        .message
        .contains("inside the definition"));
    // Unbounded recursion stops at the call depth limit with an error.
    let e = first_error("o1 sub\no1 call\no1 endsub\no1 call");
    assert!(
        e.message.contains("nested subroutine calls"),
        "{}",
        e.message
    );
    let e = first_error("o1 sub\nG0 X1\n");
    assert!(e.message.contains("end of file"), "{}", e.message);
}

#[test]
fn if_elseif_else() {
    // rs274: X2, then X4.
    assert_eq!(xs("o1 if [0]\nG0 X1\no1 elseif [1]\nG0 X2\no1 elseif [1]\nG0 X3\no1 else\nG0 X4\no1 endif"), vec![2.0]);
    assert_eq!(xs("o1 if [0]\nG0 X1\no1 else\nG0 X4\no1 endif"), vec![4.0]);
    assert_eq!(
        xs("o1 if [1]\nG0 X1\no1 else\nG0 X4\no1 endif\nG0 X5"),
        vec![1.0, 5.0]
    );
    // A false branch may hold lines that would not parse: they are skipped unread.
    assert_eq!(xs("o1 if [0]\nG0 X[1/\no1 endif\nG0 X5"), vec![5.0]);
    assert!(first_error("o1 endif").message.contains("without o1 if"));
    assert!(first_error("o1 else").message.contains("without o1 if"));
    assert!(first_error("o1 if [0]\nG0 X1\n")
        .message
        .contains("end of file"));
}

#[test]
fn loops() {
    // rs274: X0 X1 X2.
    assert_eq!(
        xs("#1=0\no1 while [#1 LT 3]\nG0 X#1\n#1=[#1+1]\no1 endwhile"),
        vec![0.0, 1.0, 2.0]
    );
    // do-while runs once even when the condition is false (rs274: X0).
    assert_eq!(
        xs("#1=0\no1 do\nG0 X#1\n#1=[#1+1]\no1 while [#1 LT 0]"),
        vec![0.0]
    );
    assert_eq!(
        xs("#1=0\no1 do\nG0 X#1\n#1=[#1+1]\no1 while [#1 LT 3]"),
        vec![0.0, 1.0, 2.0]
    );
    // repeat rounds its count (rs274: 2.6 → 3 times, 2.4 → 2 times).
    assert_eq!(xs("o1 repeat [2.6]\nG0 X1\no1 endrepeat").len(), 3);
    assert_eq!(xs("o1 repeat [2.4]\nG0 X1\no1 endrepeat").len(), 2);
    assert_eq!(xs("o1 repeat [0]\nG0 X1\no1 endrepeat\nG0 X2"), vec![2.0]);
    // break and continue (rs274: X1 X3).
    let p = "#1=0\no1 while [#1 LT 5]\n#1=[#1+1]\no2 if [#1 EQ 2]\no1 continue\no2 endif\n\
             o3 if [#1 EQ 4]\no1 break\no3 endif\nG0 X#1\no1 endwhile\nG0 X9";
    assert_eq!(xs(p), vec![1.0, 3.0, 9.0]);
    // Nested loops with a subroutine call inside.
    let p = "o9 sub\nG0 X[#1*10+#2]\no9 endsub\n#1=0\no1 while [#1 LT 2]\n#2=0\no2 repeat [2]\n\
             o9 call [#1] [#2]\n#2=[#2+1]\no2 endrepeat\n#1=[#1+1]\no1 endwhile";
    assert_eq!(xs(p), vec![0.0, 1.0, 10.0, 11.0]);
    // continue in repeat and do loops.
    // rs274: break and continue do not apply to repeat loops ("no matching while/do label").
    let e = first_error("o1 repeat [3]\no1 continue\no1 endrepeat");
    assert!(
        e.message.contains("o1 continue inside o1 repeat"),
        "{}",
        e.message
    );
    assert!(first_error("o1 repeat [3]\no1 break\no1 endrepeat")
        .message
        .contains("repeat"));
    assert_eq!(
        xs("#1=0\no1 do\n#1=[#1+1]\no1 continue\nG0 X99\no1 while [#1 LT 3]\nG0 X#1"),
        vec![3.0]
    );
    assert_eq!(
        xs("o1 do\no1 break\nG0 X99\no1 while [1]\nG0 X2"),
        vec![2.0]
    );
}

#[test]
fn endless_loops_end_with_an_error_and_the_program_goes_on() {
    let (blocks, errors) = run("o1 while [1]\no1 endwhile\nG0 X7");
    assert_eq!(errors.len(), 1);
    assert!(
        errors[0].message.contains("without producing a block"),
        "{}",
        errors[0].message
    );
    assert_eq!(
        blocks.iter().filter_map(|b| b.get('X')).collect::<Vec<_>>(),
        vec![7.0]
    );
    // With blocks in the loop the per-loop limit applies.
    let (blocks, errors) = run("#1=0\no1 while [1]\n#1=[#1+1]\no1 endwhile\nG0 X7");
    assert_eq!(errors.len(), 1);
    assert!(
        errors[0].message.contains("more than 10000 times"),
        "{}",
        errors[0].message
    );
    assert_eq!(blocks.last().unwrap().get('X'), Some(7.0));
    let (_, errors) = run("o1 do\no1 while [1]\nG0 X7");
    assert_eq!(errors.len(), 1);
    let (_, errors) = run("o1 repeat [1000000000]\no1 endrepeat");
    assert!(!errors.is_empty());
    // Nested loops multiply: the run-wide bound stops them.
    let (blocks, errors) =
        run("o1 repeat [1000]\no2 repeat [1000]\nG0 X1\no2 endrepeat\no1 endrepeat\nG0 X2");
    assert!(
        errors.iter().any(|e| e.message.contains("in this run")),
        "{errors:?}"
    );
    assert_eq!(blocks.last().unwrap().get('X'), Some(2.0));
    assert!(blocks.len() < 60_000);
}

#[test]
fn loop_errors() {
    assert!(first_error("o1 endwhile")
        .message
        .contains("without o1 while"));
    assert!(first_error("o1 break").message.contains("outside a loop"));
    // A break of a repeat is reported when first read, even in a branch not taken (rs274
    // reports it when its skipping passes the line: here after the loop, at the latest).
    let (blocks, errors) = run("o1 repeat [2]\no2 if [0]\no1 break\no2 endif\nG0 X1\no1 endrepeat");
    assert_eq!(errors[0].span.line, 3);
    assert!(errors[0].message.contains("o1 break inside o1 repeat"));
    assert!(blocks.len() <= 2);
    assert!(first_error("o1 while [1]\no2 break\no1 endwhile")
        .message
        .contains("o2 break"));
    assert!(first_error("o1 while [1]\nG0 X1\n")
        .message
        .contains("end of file inside o1 while"));
}

#[test]
fn comments_messages_and_debug_substitution() {
    let (blocks, _) =
        run("#1=5 (debug,#1 #<nope> #<_value> [#1])\n(MSG, hi there)\n(plain)\nG0 X1 ; not kept");
    assert_eq!(
        blocks[0].notes,
        vec![Note::Debug("5.000000 ###### 0.000000 [5.000000]".into())]
    );
    assert_eq!(blocks[1].notes, vec![Note::Message(" hi there".into())]);
    assert_eq!(blocks[2].notes, vec![Note::Comment("plain".into())]);
    assert!(blocks[3].notes.is_empty());
}

#[test]
fn percent_markers_and_block_delete() {
    let mut exec = Executor::from_text("\n%\nG0 X1\n%\nG0 X2 (never read)\n", Dialect::LinuxCnc);
    let mut p = Params::new();
    assert_eq!(
        exec.next_block(&mut p).unwrap().unwrap().get('X'),
        Some(1.0)
    );
    assert!(exec.next_block(&mut p).is_none());
    assert_eq!(exec.end(), Some(ProgramEnd::Percent));
    // rs274: a '%' that is not on the first non-blank line is an error.
    assert!(first_error("(c)\n%\nG0 X1").message.contains('%'));
    assert!(first_error("G0 X1\n%").message.contains('%'));
    let mut exec = Executor::from_text("/G0 X1\nG0 X2", Dialect::LinuxCnc);
    exec.honour_block_delete(true);
    assert_eq!(
        exec.next_block(&mut p).unwrap().unwrap().get('X'),
        Some(2.0)
    );
    assert_eq!(xs("/G0 X1\nG0 X2"), vec![1.0, 2.0]);
}

#[test]
fn errors_do_not_stop_the_next_line() {
    let (blocks, errors) = run("G0 X[1/0]\nG0 X1\nG0 X#<nope>\nG0 X2 (unclosed\nG0 X3");
    assert_eq!(errors.len(), 3);
    assert_eq!(
        errors.iter().map(|e| e.span.line).collect::<Vec<_>>(),
        vec![1, 3, 4]
    );
    assert_eq!(
        blocks.iter().filter_map(|b| b.get('X')).collect::<Vec<_>>(),
        vec![1.0, 3.0]
    );
}

#[test]
fn an_over_long_line_is_an_error_not_an_allocation() {
    let mut text = String::from("G0 X1\n");
    text.push_str(&"X".repeat(5000));
    text.push_str("\nG0 X2\n");
    let mut exec = Executor::from_text(&text, Dialect::LinuxCnc);
    exec.set_max_line_len(1000);
    let mut p = Params::new();
    assert!(exec.next_block(&mut p).unwrap().is_ok());
    let e = exec.next_block(&mut p).unwrap().unwrap_err();
    assert_eq!(e.span.line, 2);
    assert!(e.message.contains("5000 bytes"), "{}", e.message);
    assert_eq!(
        exec.next_block(&mut p).unwrap().unwrap().get('X'),
        Some(2.0)
    );
}

#[test]
fn open_blocks_are_bounded() {
    let text = "o1 if [1]\n".repeat(1500);
    let (_, errors) = run(&text);
    assert!(
        errors.iter().any(|e| e.message.contains("open at once")),
        "{:?}",
        errors.first()
    );
}

/// A source of `len` bytes of `x` without a newline, then one short line: never held in
/// memory, generated as it is read.
struct NoNewline {
    len: u64,
    pos: u64,
}

const TAIL: &[u8] = b"\nG0 X1\n";

impl std::io::Read for NoNewline {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let total = self.len + TAIL.len() as u64;
        let n = (buf.len() as u64).min(total.saturating_sub(self.pos)) as usize;
        for (i, b) in buf[..n].iter_mut().enumerate() {
            let at = self.pos + i as u64;
            *b = if at < self.len {
                b'x'
            } else {
                TAIL[(at - self.len) as usize]
            };
        }
        self.pos += n as u64;
        Ok(n)
    }
}

impl std::io::Seek for NoNewline {
    fn seek(&mut self, to: std::io::SeekFrom) -> std::io::Result<u64> {
        if let std::io::SeekFrom::Start(p) = to {
            self.pos = p;
        }
        Ok(self.pos)
    }
}

#[test]
fn a_huge_line_without_newline_is_an_error_and_streams_past() {
    let reader = std::io::BufReader::new(NoNewline {
        len: 64 << 20,
        pos: 0,
    });
    let mut exec = Executor::new(reader, Dialect::LinuxCnc);
    let mut p = Params::new();
    let e = exec.next_block(&mut p).unwrap().unwrap_err();
    assert!(
        e.message.contains(&format!("{} bytes long", 64u64 << 20)),
        "{}",
        e.message
    );
    assert_eq!(
        exec.next_block(&mut p).unwrap().unwrap().get('X'),
        Some(1.0)
    );
    assert!(exec.next_block(&mut p).is_none());
}

/// Deliberate differences from rs274 (LinuxCNC 2.9.0~pre1), where its label-based skipping
/// gives results that contradict its own documentation. Each program's rs274 output is noted.
#[test]
fn where_rs274_is_wrong_we_follow_the_documented_semantics() {
    // rs274 prints X1 only: leaving a while loop by break leaves its `doing_break` flag set,
    // and the next do-while loop then stops after its first pass.
    let p =
        "o1 while [1]\no1 break\no1 endwhile\n#2=0\no2 do\n#2=[#2+1]\nG0 X#2\no2 while [#2 LT 3]";
    assert_eq!(xs(p), vec![1.0, 2.0, 3.0]);
    // rs274 prints X1 only: the continue skips forward, reads the (not executed) break of the
    // same loop on the way and obeys it.
    let p = "#1=0\no1 do\n#1=[#1+1]\nG0 X#1\no2 if [1]\no1 continue\no2 endif\n\
             o3 if [0]\no1 break\no3 endif\no1 while [#1 LT 3]";
    assert_eq!(xs(p), vec![1.0, 2.0, 3.0]);
    // rs274 prints X1 twice: a do-while inside a skipped branch restarts the repeat.
    let p = "o1 repeat [1]\nG0 X1\no2 if [0]\no3 do\no3 while [0]\no2 endif\no1 endrepeat";
    assert_eq!(xs(p), vec![1.0]);
    // rs274 prints X1 twice: so does a repeat [0] inside a skipped branch.
    let p = "o1 repeat [1]\nG0 X1\no2 if [0]\no3 repeat [0]\no3 endrepeat\no2 endif\no1 endrepeat";
    assert_eq!(xs(p), vec![1.0]);
}
