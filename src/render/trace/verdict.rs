//! What `trace --explain` says the article's program does with a file: the verdict line, in
//! English or Traditional Chinese.

use super::{Language, axis_letters, plain};

/// The first line of `--explain`: what the article's program does with the file as a whole, in
/// one of four words (`reads it as written`, `misreads it`, `rejects it`, `crashes on it`;
/// `如實讀入`, `讀錯`, `拒絕`, `當掉`), and why.
pub fn verdict_line(verdict: &crate::bvh::article::Verdict, language: Language) -> String {
    use crate::bvh::article::{Crash, Misread, Rejection, Step, Verdict};
    let zh = language == Language::Chinese;
    let at = |place: &crate::bvh::article::Place| {
        if zh {
            format!("第 {} 行第 {} 欄", place.line, place.column)
        } else {
            format!("line {}, column {}", place.line, place.column)
        }
    };
    let why = match verdict {
        Verdict::ReadsAsWritten => {
            if zh {
                "如實讀入：print 與每個影格的 draw 都和檔案所寫的相同（關節、名字、OFFSET、平移與旋轉）"
                    .to_string()
            } else {
                "reads it as written: print and the draw of every frame are what the file says (joints, names, OFFSETs, translations, rotations)".to_string()
            }
        }
        Verdict::Rejects(rejection) => {
            let reason = match (rejection, zh) {
                (Rejection::NotHierarchy, false) => {
                    "its first nine bytes are not HIERARCHY".to_string()
                }
                (Rejection::NotHierarchy, true) => "檔案的前九個位元組不是 HIERARCHY".to_string(),
                (Rejection::Empty, false) => {
                    "the file is empty: new unsigned char[0] gives a buffer of no bytes, and the check of the header compares the byte after it with the H of HIERARCHY (valgrind reports that read, AddressSanitizer does not); it is not H".to_string()
                }
                (Rejection::Empty, true) => {
                    "檔案是空的：new unsigned char[0] 給出零個位元組的緩衝區，檢查檔頭時拿它後面的那個位元組和 HIERARCHY 的 H 比較（valgrind 回報這次讀取，AddressSanitizer 不會），那不是 H".to_string()
                }
                (Rejection::FormatError { byte, at: place }, _) => {
                    let shown = match byte {
                        0x21..=0x7E => (*byte as char).to_string(),
                        _ => format!("\\x{byte:02X}"),
                    };
                    let printed = format!("_{shown}_ _{byte}_ file format error!!");
                    if zh {
                        format!(
                            "{}的位元組在分派的 switch 裡沒有對應的 case，它印出 {printed}",
                            at(place)
                        )
                    } else {
                        format!(
                            "at {} its dispatcher meets a byte it has no case for and prints {printed}",
                            at(place)
                        )
                    }
                }
                (Rejection::Nul { at: place }, false) => format!(
                    "at {} its dispatcher meets a 0 byte, which it takes for the end of its buffer",
                    at(place)
                ),
                (Rejection::Nul { at: place }, true) => {
                    format!("{}是一個 0 位元組，它當成緩衝區的結尾", at(place))
                }
                (Rejection::OneJoint, false) => {
                    "a skeleton of one joint and no frames (jointCount == 1)".to_string()
                }
                (Rejection::OneJoint, true) => {
                    "只有一個關節、沒有影格（jointCount == 1）".to_string()
                }
            };
            if zh {
                format!(
                    "拒絕：{reason}；loadFile 傳回 0（init 接著照樣 print，空的根關節讓它當掉）"
                )
            } else {
                format!(
                    "rejects it: {reason}; loadFile returns 0 (init then prints the null root anyway, which crashes)"
                )
            }
        }
        Verdict::Crashes(crash) => {
            let step = |step: &Step| match (step, zh) {
                (Step::Header, false) => "the check of the header".to_string(),
                (Step::Header, true) => "檢查檔頭的迴圈".to_string(),
                (Step::RootName, false) => "newNode, for the root's name".to_string(),
                (Step::RootName, true) => "讀根關節名字的 newNode".to_string(),
                (Step::RootOffset, false) => "the reading of the root's OFFSET".to_string(),
                (Step::RootOffset, true) => "讀根關節 OFFSET 的步驟".to_string(),
                (Step::RootChannels, false) => {
                    "the scan for the root's first r (its rotation channels)".to_string()
                }
                (Step::RootChannels, true) => "找根關節第一個 r（旋轉通道）的掃描".to_string(),
                (Step::Hierarchy, false) => "the loop over the hierarchy".to_string(),
                (Step::Hierarchy, true) => "讀層級結構的迴圈".to_string(),
                (Step::Frames, false) => "the scan for the F of Frames".to_string(),
                (Step::Frames, true) => "找 Frames 的 F 的掃描".to_string(),
                (Step::FrameTime, false) => "the scan for the F of Frame Time".to_string(),
                (Step::FrameTime, true) => "找 Frame Time 的 F 的掃描".to_string(),
                (Step::Rows(frame), false) => format!("the row loop, in frame {frame},"),
                (Step::Rows(frame), true) => format!("讀資料列的迴圈在第 {frame} 個影格"),
            };
            let reason = match (crash, zh) {
                (Crash::FileLength { length }, false) => format!(
                    "the file is {length} bytes long, which int iFileSize holds as {}: new unsigned char[iFileSize] throws std::bad_alloc, and the program aborts",
                    *length as u32 as i32
                ),
                (Crash::FileLength { length }, true) => format!(
                    "檔案長 {length} 個位元組，int iFileSize 存成 {}：new unsigned char[iFileSize] 丟出 std::bad_alloc，程式中止",
                    *length as u32 as i32
                ),
                (Crash::ReadPast { step: s, at: place }, false) => format!(
                    "{} reads past the end of its buffer ({}, the end of the file)",
                    step(s),
                    at(place)
                ),
                (Crash::ReadPast { step: s, at: place }, true) => {
                    format!("{}讀過了緩衝區的結尾（{}，檔案的結尾）", step(s), at(place))
                }
                (Crash::SeventeenthChild { parent }, false) => format!(
                    "'{parent}' gets a 17th child: child[16] lands on childNum (the assert compares with 24, not 16), and print and draw go astray"
                ),
                (Crash::SeventeenthChild { parent }, true) => format!(
                    "'{parent}' 有第 17 個子關節：child[16] 寫到 childNum 上（assert 比的是 24 而不是 16），print 和 draw 從此出錯"
                ),
                (Crash::UnsetRows { frames }, false) => format!(
                    "a skeleton of one joint (jointCount == 1): loadFile calls clear(), which deletes {frames} row pointers it never set"
                ),
                (Crash::UnsetRows { frames }, true) => format!(
                    "只有一個關節（jointCount == 1）：loadFile 呼叫 clear()，它 delete 了 {frames} 個從未設定的資料列指標"
                ),
                (Crash::Allocation { frames }, false) => format!(
                    "(unsigned)atoi makes Frames: {frames}, and new float*[{frames}] asks for {} bytes before it reads a row: std::bad_alloc, abort",
                    u64::from(*frames) * 8
                ),
                (Crash::Allocation { frames }, true) => format!(
                    "(unsigned)atoi 把 Frames: 讀成 {frames}，new float*[{frames}] 在讀任何一列之前就要 {} 個位元組：std::bad_alloc，程式中止",
                    u64::from(*frames) * 8
                ),
                (Crash::NoFrames, false) => {
                    "loadFile returns 1 with frameCount 0, and draw reads row 0 of an empty array"
                        .to_string()
                }
                (Crash::NoFrames, true) => {
                    "loadFile 傳回 1，但 frameCount 是 0，draw 讀了空陣列的第 0 列".to_string()
                }
                (
                    Crash::RowTooShort {
                        joint,
                        column,
                        width,
                    },
                    false,
                ) => format!(
                    "draw's pFrame reads column [{column}] for '{joint}', past the end of a row of {width} values (jointCount * 3 + 3)"
                ),
                (
                    Crash::RowTooShort {
                        joint,
                        column,
                        width,
                    },
                    true,
                ) => format!(
                    "draw 的 pFrame 為 '{joint}' 讀第 [{column}] 欄，超過一列 {width} 個值（jointCount * 3 + 3）的結尾"
                ),
            };
            if zh {
                format!("當掉：{reason}")
            } else {
                format!("crashes on it: {reason}")
            }
        }
        Verdict::Misreads(misread) => {
            let reason = match (misread, zh) {
                (Misread::Cut { read, length }, false) => format!(
                    "it reads only the first {read} of the file's {length} bytes: int iFileSize keeps the length modulo 4 GiB"
                ),
                (Misread::Cut { read, length }, true) => format!(
                    "檔案有 {length} 個位元組，它只讀前 {read} 個：int iFileSize 只留下長度除以 4 GiB 的餘數"
                ),
                (Misread::Garbage(words), _) => {
                    let each: Vec<String> = words
                        .iter()
                        .map(|(word, value, place)| {
                            if zh {
                                format!("{}的 '{word}' 讀成 {value}", at(place))
                            } else {
                                format!("'{word}' ({}) as {value}", at(place))
                            }
                        })
                        .collect();
                    if zh {
                        format!("atof 把不是數字的字讀成數字，不發一語：{}", each.join("，"))
                    } else {
                        format!(
                            "atof reads words that are not numbers, without a word: {}",
                            each.join(", ")
                        )
                    }
                }
                (Misread::Joints { article, file }, false) => format!(
                    "its tree holds {article} joints and End Sites where the file has {file}"
                ),
                (Misread::Joints { article, file }, true) => {
                    format!("它的樹只有 {article} 個關節與 End Site，檔案裡有 {file} 個")
                }
                (Misread::Name { file, article }, false) => {
                    format!("it keeps the name '{file}' as '{article}'")
                }
                (Misread::Name { file, article }, true) => {
                    format!("名字 '{file}' 被存成 '{article}'")
                }
                (
                    Misread::Offset {
                        joint,
                        article,
                        file,
                    },
                    false,
                ) => format!(
                    "it reads the OFFSET of '{joint}' as {} where the file says {}",
                    plain(article),
                    plain(file)
                ),
                (
                    Misread::Offset {
                        joint,
                        article,
                        file,
                    },
                    true,
                ) => format!(
                    "'{joint}' 的 OFFSET 讀成 {}，檔案寫的是 {}",
                    plain(article),
                    plain(file)
                ),
                (Misread::Frames { article, file }, false) => {
                    format!("its frameCount is {article} where the file has {file} frames")
                }
                (Misread::Frames { article, file }, true) => {
                    format!("它的 frameCount 是 {article}，檔案有 {file} 個影格")
                }
                (
                    Misread::Translation {
                        joint,
                        frame,
                        article,
                        file,
                    },
                    false,
                ) => format!(
                    "in frame {frame} it translates '{joint}' by {} where the file means {}",
                    plain(article),
                    plain(file)
                ),
                (
                    Misread::Translation {
                        joint,
                        frame,
                        article,
                        file,
                    },
                    true,
                ) => format!(
                    "第 {frame} 個影格把 '{joint}' 平移 {}，檔案的意思是 {}",
                    plain(article),
                    plain(file)
                ),
                (
                    Misread::Rotations {
                        joint,
                        frame,
                        article,
                        file,
                    },
                    _,
                ) => {
                    let axes = |turns: &[(usize, f32)]| axis_letters(turns.iter().map(|t| t.0), zh);
                    let values = |turns: &[(usize, f32)]| {
                        plain(&turns.iter().map(|t| t.1).collect::<Vec<_>>())
                    };
                    let same_axes = axes(article) == axes(file);
                    match (same_axes, article.is_empty(), zh) {
                        (false, true, false) => format!(
                            "it does not turn '{joint}' at all, where the file turns it about {}",
                            axes(file)
                        ),
                        (false, true, true) => {
                            format!("它完全不轉 '{joint}'，檔案要它依序繞 {} 軸旋轉", axes(file))
                        }
                        (false, false, false) => format!(
                            "it turns '{joint}' about {} where the file says {}",
                            axes(article),
                            axes(file)
                        ),
                        (false, false, true) => format!(
                            "它讓 '{joint}' 依序繞 {} 軸旋轉，檔案寫的是 {}",
                            axes(article),
                            axes(file)
                        ),
                        (true, _, false) => format!(
                            "in frame {frame} it turns '{joint}' by {} about {} where the file says {}",
                            values(article),
                            axes(article),
                            values(file)
                        ),
                        (true, _, true) => format!(
                            "第 {frame} 個影格讓 '{joint}' 繞 {} 軸轉 {}，檔案寫的是 {}",
                            axes(article),
                            values(article),
                            values(file)
                        ),
                    }
                }
                (Misread::NoName { at: place }, false) => format!(
                    "a joint on line {} has no name: newNode copies no byte and writes its terminator at name[-1] (UndefinedBehaviorSanitizer: index -1 out of bounds), and keeps the joint with an empty name",
                    place.line
                ),
                (Misread::NoName { at: place }, true) => format!(
                    "第 {} 行的關節沒有名字：newNode 一個位元組也沒複製，把結尾的 0 寫到 name[-1]（UndefinedBehaviorSanitizer：索引 -1 超出範圍），這個關節就以空的名字留下",
                    place.line
                ),
                (Misread::Refused, false) => {
                    "it loads this file, which bvhview refuses (below)".to_string()
                }
                (Misread::Refused, true) => "它載入了 bvhview 拒絕的這個檔案（見下）".to_string(),
                (
                    Misread::MatrixStack {
                        overflow,
                        wrong,
                        drawn,
                    },
                    false,
                ) => format!(
                    "its draw pushes one matrix per joint and GL's stack holds {}: at '{overflow}' \
                     glPushMatrix overflows and is ignored, the pops after it take the matrices \
                     of joints above, and {} is drawn from a matrix that is not its own{}",
                    crate::bvh::article::GL_STACK_DEPTH,
                    wrong
                        .as_ref()
                        .map_or("the floor".to_string(), |joint| format!("'{joint}'")),
                    drawn.map_or(String::new(), |(drawn, meant)| format!(
                        ": in frame 0 at {}, where the file puts it at {}",
                        plain(&drawn),
                        plain(&meant)
                    ))
                ),
                (
                    Misread::MatrixStack {
                        overflow,
                        wrong,
                        drawn,
                    },
                    true,
                ) => format!(
                    "它的 draw 每個關節推入一個矩陣，GL 的矩陣堆疊只有 {} 層：到了 '{overflow}'，\
                     glPushMatrix 溢位而被忽略，之後的彈出拿走了上層關節的矩陣，{}用的不是自己的矩陣{}",
                    crate::bvh::article::GL_STACK_DEPTH,
                    wrong
                        .as_ref()
                        .map_or("地板".to_string(), |joint| format!("'{joint}' ")),
                    drawn.map_or(String::new(), |(drawn, meant)| format!(
                        "：第 0 個影格畫在 {}，檔案要它在 {}",
                        plain(&drawn),
                        plain(&meant)
                    ))
                ),
            };
            if zh {
                format!("讀錯：{reason}")
            } else {
                format!("misreads it: {reason}")
            }
        }
    };
    if zh {
        format!("// 原文的程式對這個檔案：{why}")
    } else {
        format!("// what the article's program does with this file: {why}")
    }
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
