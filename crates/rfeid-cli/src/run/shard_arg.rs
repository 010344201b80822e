//! `--shard K/N` (or `auto`, from Slurm's job-array variables).
use crate::diagnostics::Failure;

/// Parses `K/N` (0 ≤ K < N) or `auto` (from Slurm's job-array variables).
pub fn parse_shard(text: &str) -> Result<(usize, usize), Failure> {
    if text == "auto" {
        return from_slurm();
    }
    let bad = || {
        Failure::input_msg(format!(
            "--shard '{text}': expected K/N with 0 <= K < N (e.g. 0/4), or auto"
        ))
    };
    let (k, n) = text.split_once('/').ok_or_else(bad)?;
    let k: usize = k.trim().parse().map_err(|_| bad())?;
    let n: usize = n.trim().parse().map_err(|_| bad())?;
    checked(k, n, text)
}

/// `--shard auto`: the shard of this task of a Slurm job array.
fn from_slurm() -> Result<(usize, usize), Failure> {
    let var = |name: &str| -> Result<Option<usize>, Failure> {
        match std::env::var(name) {
            Err(_) => Ok(None),
            Ok(v) => v.trim().parse().map(Some).map_err(|_| {
                Failure::input_msg(format!("--shard auto: {name}='{v}' is not a count"))
            }),
        }
    };
    let (id, count) = (var("SLURM_ARRAY_TASK_ID")?, var("SLURM_ARRAY_TASK_COUNT")?);
    let (Some(id), Some(count)) = (id, count) else {
        let unset: Vec<&str> = [
            ("SLURM_ARRAY_TASK_ID", id),
            ("SLURM_ARRAY_TASK_COUNT", count),
        ]
        .into_iter()
        .filter(|(_, v)| v.is_none())
        .map(|(name, _)| name)
        .collect();
        return Err(Failure::input_msg(format!(
            "--shard auto: {} not set (not in a Slurm job array?)",
            match unset.as_slice() {
                [one] => format!("{one} is"),
                _ => format!("{} are", unset.join(" and ")),
            }
        )));
    };
    if let Some(step) = var("SLURM_ARRAY_TASK_STEP")?.filter(|&s| s != 1) {
        return Err(Failure::input_msg(format!(
            "--shard auto: the job array steps by {step} (SLURM_ARRAY_TASK_STEP): shards need a contiguous array such as --array=0-{}, or --shard K/N given explicitly",
            count.saturating_sub(1)
        )));
    }
    let min = var("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
    if let Some(max) = var("SLURM_ARRAY_TASK_MAX")? {
        if max.checked_sub(min).map(|span| span + 1) != Some(count) {
            return Err(Failure::input_msg(format!(
                "--shard auto: the job array's tasks {min} to {max} are not {count} contiguous ones (a list such as --array=3,7,9?): shards need a contiguous array such as --array=0-{}, or --shard K/N given explicitly",
                count.saturating_sub(1)
            )));
        }
    }
    let k = id.checked_sub(min).ok_or_else(|| {
        Failure::input_msg(format!(
            "--shard auto: SLURM_ARRAY_TASK_ID {id} is below SLURM_ARRAY_TASK_MIN {min}"
        ))
    })?;
    checked(k, count, "auto")
}

/// Shard `k` of `n` must exist.
fn checked(k: usize, n: usize, text: &str) -> Result<(usize, usize), Failure> {
    if n == 0 || k >= n {
        return Err(Failure::input_msg(format!(
            "--shard {text}: shard {k} of {n} does not exist (0 <= K < N)"
        )));
    }
    Ok((k, n))
}

/// A shard file refused: bad input naming the file.
pub fn shard_failure(e: rfeid::io::shard_file::ShardError) -> Failure {
    Failure::input_msg(e)
}
