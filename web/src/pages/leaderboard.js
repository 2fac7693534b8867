// /leaderboard/{game}: not yet served by the game service; the page says so.
document.getElementById("board-status").textContent = "The leaderboard is not available yet.";
