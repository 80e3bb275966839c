//! What `trace --explain` says the article's program does with a file: the verdict line, in
//! English or Traditional Chinese.
//!
//! Every case is one row of a two-column table, `[English, Chinese]`: a reader sees the two
//! languages side by side, and a case cannot be said in one and forgotten in the other. Each
//! phrase builds both columns; `verdict_line` says the one asked for.

use super::language::{Both, Language, axis_letters, both, plain};
use crate::bvh::article::{Crash, Misread, Place, Rejection, Step, Verdict};

/// The first line of `--explain`: what the article's program does with the file as a whole, in
/// one of four words (`reads it as written`, `misreads it`, `rejects it`, `crashes on it`;
/// `如實讀入`, `讀錯`, `拒絕`, `當掉`), and why.
pub fn verdict_line(verdict: &Verdict, language: Language) -> String {
    let [english, chinese] = match verdict {
        Verdict::ReadsAsWritten => both(
            "reads it as written: print and the draw of every frame are what the file says (joints, names, OFFSETs, translations, rotations)",
            "如實讀入：print 與每個影格的 draw 都和檔案所寫的相同（關節、名字、OFFSET、平移與旋轉）",
        ),
        Verdict::Rejects(rejection) => {
            let [english, chinese] = rejection_reason(rejection);
            [
                format!(
                    "rejects it: {english}; loadFile returns 0 (init then prints the null root anyway, which crashes)"
                ),
                format!(
                    "拒絕：{chinese}；loadFile 傳回 0（init 接著照樣 print，空的根關節讓它當掉）"
                ),
            ]
        }
        Verdict::Crashes(crash) => {
            let [english, chinese] = crash_reason(crash);
            [
                format!("crashes on it: {english}"),
                format!("當掉：{chinese}"),
            ]
        }
        Verdict::Misreads(misread) => {
            let [english, chinese] = misread_reason(misread);
            [
                format!("misreads it: {english}"),
                format!("讀錯：{chinese}"),
            ]
        }
    };
    match language {
        Language::English => {
            format!("// what the article's program does with this file: {english}")
        }
        Language::Chinese => format!("// 原文的程式對這個檔案：{chinese}"),
    }
}

/// Where in the file a verdict points: `line 3, column 7`, `第 3 行第 7 欄`.
fn at(place: &Place) -> Both {
    [
        format!("line {}, column {}", place.line, place.column),
        format!("第 {} 行第 {} 欄", place.line, place.column),
    ]
}

/// Why `loadFile` returns 0: the header is wrong, the dispatcher meets a byte it cannot place,
/// or the skeleton is a single joint.
fn rejection_reason(rejection: &Rejection) -> Both {
    match rejection {
        Rejection::NotHierarchy => both(
            "its first nine bytes are not HIERARCHY",
            "檔案的前九個位元組不是 HIERARCHY",
        ),
        Rejection::Empty => both(
            "the file is empty: new unsigned char[0] gives a buffer of no bytes, and the check of the header compares the byte after it with the H of HIERARCHY (valgrind reports that read, AddressSanitizer does not); it is not H",
            "檔案是空的：new unsigned char[0] 給出零個位元組的緩衝區，檢查檔頭時拿它後面的那個位元組和 HIERARCHY 的 H 比較（valgrind 回報這次讀取，AddressSanitizer 不會），那不是 H",
        ),
        Rejection::FormatError { byte, at: place } => {
            let shown = match byte {
                0x21..=0x7E => (*byte as char).to_string(),
                _ => format!("\\x{byte:02X}"),
            };
            let printed = format!("_{shown}_ _{byte}_ file format error!!");
            let [english, chinese] = at(place);
            [
                format!(
                    "at {english} its dispatcher meets a byte it has no case for and prints {printed}"
                ),
                format!("{chinese}的位元組在分派的 switch 裡沒有對應的 case，它印出 {printed}"),
            ]
        }
        Rejection::Nul { at: place } => {
            let [english, chinese] = at(place);
            [
                format!(
                    "at {english} its dispatcher meets a 0 byte, which it takes for the end of its buffer"
                ),
                format!("{chinese}是一個 0 位元組，它當成緩衝區的結尾"),
            ]
        }
        Rejection::OneJoint => both(
            "a skeleton of one joint and no frames (jointCount == 1)",
            "只有一個關節、沒有影格（jointCount == 1）",
        ),
    }
}

/// The step of `loadFile` a crash happens in, as the verdict names it.
fn step_name(step: &Step) -> Both {
    match step {
        Step::Header => both("the check of the header", "檢查檔頭的迴圈"),
        Step::RootName => both("newNode, for the root's name", "讀根關節名字的 newNode"),
        Step::RootOffset => both("the reading of the root's OFFSET", "讀根關節 OFFSET 的步驟"),
        Step::RootChannels => both(
            "the scan for the root's first r (its rotation channels)",
            "找根關節第一個 r（旋轉通道）的掃描",
        ),
        Step::Hierarchy => both("the loop over the hierarchy", "讀層級結構的迴圈"),
        Step::Frames => both("the scan for the F of Frames", "找 Frames 的 F 的掃描"),
        Step::FrameTime => both(
            "the scan for the F of Frame Time",
            "找 Frame Time 的 F 的掃描",
        ),
        Step::Rows(frame) => [
            format!("the row loop, in frame {frame},"),
            format!("讀資料列的迴圈在第 {frame} 個影格"),
        ],
    }
}

/// Why the article's program crashes: what it allocates, reads or frees that it must not.
fn crash_reason(crash: &Crash) -> Both {
    match crash {
        Crash::FileLength { length } => {
            let held = *length as u32 as i32;
            [
                format!(
                    "the file is {length} bytes long, which int iFileSize holds as {held}: new unsigned char[iFileSize] throws std::bad_alloc, and the program aborts"
                ),
                format!(
                    "檔案長 {length} 個位元組，int iFileSize 存成 {held}：new unsigned char[iFileSize] 丟出 std::bad_alloc，程式中止"
                ),
            ]
        }
        Crash::ReadPast { step, at: place } => {
            let ([step_en, step_zh], [at_en, at_zh]) = (step_name(step), at(place));
            [
                format!(
                    "{step_en} reads past the end of its buffer ({at_en}, the end of the file)"
                ),
                format!("{step_zh}讀過了緩衝區的結尾（{at_zh}，檔案的結尾）"),
            ]
        }
        Crash::SeventeenthChild { parent } => [
            format!(
                "'{parent}' gets a 17th child: child[16] lands on childNum (the assert compares with 24, not 16), and print and draw go astray"
            ),
            format!(
                "'{parent}' 有第 17 個子關節：child[16] 寫到 childNum 上（assert 比的是 24 而不是 16），print 和 draw 從此出錯"
            ),
        ],
        Crash::UnsetRows { frames } => [
            format!(
                "a skeleton of one joint (jointCount == 1): loadFile calls clear(), which deletes {frames} row pointers it never set"
            ),
            format!(
                "只有一個關節（jointCount == 1）：loadFile 呼叫 clear()，它 delete 了 {frames} 個從未設定的資料列指標"
            ),
        ],
        Crash::Allocation { frames } => {
            let bytes = u64::from(*frames) * 8;
            [
                format!(
                    "(unsigned)atoi makes Frames: {frames}, and new float*[{frames}] asks for {bytes} bytes before it reads a row: std::bad_alloc, abort"
                ),
                format!(
                    "(unsigned)atoi 把 Frames: 讀成 {frames}，new float*[{frames}] 在讀任何一列之前就要 {bytes} 個位元組：std::bad_alloc，程式中止"
                ),
            ]
        }
        Crash::NoFrames => both(
            "loadFile returns 1 with frameCount 0, and draw reads row 0 of an empty array",
            "loadFile 傳回 1，但 frameCount 是 0，draw 讀了空陣列的第 0 列",
        ),
        Crash::RowTooShort {
            joint,
            column,
            width,
        } => [
            format!(
                "draw's pFrame reads column [{column}] for '{joint}', past the end of a row of {width} values (jointCount * 3 + 3)"
            ),
            format!(
                "draw 的 pFrame 為 '{joint}' 讀第 [{column}] 欄，超過一列 {width} 個值（jointCount * 3 + 3）的結尾"
            ),
        ],
    }
}

/// Why the article's program loads the file but holds something other than what it says.
fn misread_reason(misread: &Misread) -> Both {
    match misread {
        Misread::Cut { read, length } => [
            format!(
                "it reads only the first {read} of the file's {length} bytes: int iFileSize keeps the length modulo 4 GiB"
            ),
            format!(
                "檔案有 {length} 個位元組，它只讀前 {read} 個：int iFileSize 只留下長度除以 4 GiB 的餘數"
            ),
        ],
        Misread::Garbage(words) => garbage(words),
        Misread::Joints { article, file } => [
            format!("its tree holds {article} joints and End Sites where the file has {file}"),
            format!("它的樹只有 {article} 個關節與 End Site，檔案裡有 {file} 個"),
        ],
        Misread::Name { file, article } => [
            format!("it keeps the name '{file}' as '{article}'"),
            format!("名字 '{file}' 被存成 '{article}'"),
        ],
        Misread::Offset {
            joint,
            article,
            file,
        } => {
            let (article, file) = (plain(article), plain(file));
            [
                format!("it reads the OFFSET of '{joint}' as {article} where the file says {file}"),
                format!("'{joint}' 的 OFFSET 讀成 {article}，檔案寫的是 {file}"),
            ]
        }
        Misread::Frames { article, file } => [
            format!("its frameCount is {article} where the file has {file} frames"),
            format!("它的 frameCount 是 {article}，檔案有 {file} 個影格"),
        ],
        Misread::Translation {
            joint,
            frame,
            article,
            file,
        } => {
            let (article, file) = (plain(article), plain(file));
            [
                format!(
                    "in frame {frame} it translates '{joint}' by {article} where the file means {file}"
                ),
                format!("第 {frame} 個影格把 '{joint}' 平移 {article}，檔案的意思是 {file}"),
            ]
        }
        Misread::Rotations {
            joint,
            frame,
            article,
            file,
        } => rotations(joint, *frame, article, file),
        Misread::NoName { at: place } => {
            let line = place.line;
            [
                format!(
                    "a joint on line {line} has no name: newNode copies no byte and writes its terminator at name[-1] (UndefinedBehaviorSanitizer: index -1 out of bounds), and keeps the joint with an empty name"
                ),
                format!(
                    "第 {line} 行的關節沒有名字：newNode 一個位元組也沒複製，把結尾的 0 寫到 name[-1]（UndefinedBehaviorSanitizer：索引 -1 超出範圍），這個關節就以空的名字留下"
                ),
            ]
        }
        Misread::Refused => both(
            "it loads this file, which bvhview refuses (below)",
            "它載入了 bvhview 拒絕的這個檔案（見下）",
        ),
        Misread::MatrixStack {
            overflow,
            wrong,
            drawn,
        } => matrix_stack(overflow, wrong.as_deref(), *drawn),
    }
}

/// The words `atof` reads as numbers without a word, each with where it stands and what it
/// became.
fn garbage(words: &[(String, f32, Place)]) -> Both {
    let (mut english, mut chinese) = (Vec::new(), Vec::new());
    for (word, value, place) in words {
        let [at_en, at_zh] = at(place);
        english.push(format!("'{word}' ({at_en}) as {value}"));
        chinese.push(format!("{at_zh}的 '{word}' 讀成 {value}"));
    }
    [
        format!(
            "atof reads words that are not numbers, without a word: {}",
            english.join(", ")
        ),
        format!(
            "atof 把不是數字的字讀成數字，不發一語：{}",
            chinese.join("，")
        ),
    ]
}

/// A joint turned about other axes than the file's (or not at all), or by other angles in one
/// frame.
fn rotations(joint: &str, frame: usize, article: &[(usize, f32)], file: &[(usize, f32)]) -> Both {
    let axes = |turns: &[(usize, f32)], zh: bool| axis_letters(turns.iter().map(|t| t.0), zh);
    let values = |turns: &[(usize, f32)]| plain(&turns.iter().map(|t| t.1).collect::<Vec<_>>());
    let (article_en, article_zh) = (axes(article, false), axes(article, true));
    let (file_en, file_zh) = (axes(file, false), axes(file, true));
    // Axes compare the same in either language: the letters are the same, only the separator
    // differs.
    if article_en != file_en {
        if article.is_empty() {
            return [
                format!(
                    "it does not turn '{joint}' at all, where the file turns it about {file_en}"
                ),
                format!("它完全不轉 '{joint}'，檔案要它依序繞 {file_zh} 軸旋轉"),
            ];
        }
        return [
            format!("it turns '{joint}' about {article_en} where the file says {file_en}"),
            format!("它讓 '{joint}' 依序繞 {article_zh} 軸旋轉，檔案寫的是 {file_zh}"),
        ];
    }
    let (turned, said) = (values(article), values(file));
    [
        format!(
            "in frame {frame} it turns '{joint}' by {turned} about {article_en} where the file says {said}"
        ),
        format!("第 {frame} 個影格讓 '{joint}' 繞 {article_zh} 軸轉 {turned}，檔案寫的是 {said}"),
    ]
}

/// GL's matrix stack overflows under the article's draw: which joint it overflows at, which is
/// drawn from a matrix not its own, and where that joint lands in frame 0.
fn matrix_stack(overflow: &str, wrong: Option<&str>, drawn: Option<([f32; 3], [f32; 3])>) -> Both {
    let depth = crate::bvh::article::GL_STACK_DEPTH;
    let (wrong_en, wrong_zh) = match wrong {
        Some(joint) => (format!("'{joint}'"), format!("'{joint}' ")),
        None => ("the floor".to_string(), "地板".to_string()),
    };
    let (drawn_en, drawn_zh) = match drawn {
        Some((drawn, meant)) => (
            format!(
                ": in frame 0 at {}, where the file puts it at {}",
                plain(&drawn),
                plain(&meant)
            ),
            format!(
                "：第 0 個影格畫在 {}，檔案要它在 {}",
                plain(&drawn),
                plain(&meant)
            ),
        ),
        None => (String::new(), String::new()),
    };
    [
        format!(
            "its draw pushes one matrix per joint and GL's stack holds {depth}: at '{overflow}' \
             glPushMatrix overflows and is ignored, the pops after it take the matrices \
             of joints above, and {wrong_en} is drawn from a matrix that is not its own{drawn_en}"
        ),
        format!(
            "它的 draw 每個關節推入一個矩陣，GL 的矩陣堆疊只有 {depth} 層：到了 '{overflow}'，\
             glPushMatrix 溢位而被忽略，之後的彈出拿走了上層關節的矩陣，{wrong_zh}用的不是自己的矩陣{drawn_zh}"
        ),
    ]
}

/// The line after the verdict when the article's draw runs past GL's matrix stack: what
/// `glGetError` says after its pushes and pops (measured with `bench/glut/run.sh`), whatever the
/// verdict. A chain alone still draws right: every sphere is drawn on the way down.
pub fn gl_stack_line(stack: &crate::bvh::article::GlStack, language: Language) -> String {
    let crate::bvh::article::GlStack {
        deepest,
        overflows,
        first,
        underflows,
    } = stack;
    let depth = crate::bvh::article::GL_STACK_DEPTH;
    match language {
        Language::English => format!(
            "// GL's modelview stack holds {depth} matrices, and the article's draw would hold {deepest} at once (the view, and one per joint and End Site down its deepest path): glGetError says GL_STACK_OVERFLOW after each of {overflows} pushes, from '{first}' on, and GL_STACK_UNDERFLOW after each of {underflows} pops"
        ),
        Language::Chinese => format!(
            "// GL 的模型檢視矩陣堆疊只有 {depth} 層，原文的 draw 同時要放 {deepest} 個矩陣（檢視矩陣，加上最深一條路徑上每個關節與 End Site 各一個）：glGetError 在 {overflows} 次推入後都回報 GL_STACK_OVERFLOW（從 '{first}' 的推入起），在 {underflows} 次彈出後都回報 GL_STACK_UNDERFLOW"
        ),
    }
}
